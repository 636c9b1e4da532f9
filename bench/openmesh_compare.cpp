// SPDX-License-Identifier: GPL-3.0-or-later
// CPU time per sweep of OpenMesh's tangential Laplacian (JacobiLaplaceSmootherT,
// tangential component, C1 continuity) beside sodt's default smoothing and
// sodt with the deviation bound off, on one mesh, one thread, in one run.

#include <sodt/params.h>
#include <sodt_io/mesh.h>
#include <sodt_io/prebuilt.h>

#include <OpenMesh/Core/IO/MeshIO.hh>
#include <OpenMesh/Core/Mesh/TriMesh_ArrayKernelT.hh>
#include <OpenMesh/Tools/Smoother/JacobiLaplaceSmootherT.hh>

#include <vcg/complex/algorithms/update/bounding.h>
#include <vcg/complex/complex.h>
#include <wrap/io_trimesh/import_off.h>
#include <wrap/io_trimesh/import_ply.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace {

using OMesh = OpenMesh::TriMesh_ArrayKernelT<>;

struct Options {
  std::string mesh;
  int sweeps = sodt::SodtParams{}.iterations;
  int repeats = 3;
};

/// CPU time of the process in ms: with one thread, the time the run took on
/// the processor, whatever else the machine is doing.
double cpuMs() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return 1e3 * double(t.tv_sec) + 1e-6 * double(t.tv_nsec);
}

bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() && s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}

/// The fastest of `repeats` calls of run(), each after reset(), in ms of CPU time.
double bestOf(int repeats, const std::function<void()>& reset, const std::function<void()>& run) {
  double best = 1e300;
  for (int k = 0; k < repeats; ++k) {
    reset();
    const double t0 = cpuMs();
    run();
    best = std::min(best, cpuMs() - t0);
  }
  return best;
}

/// One sodt call with the library's defaults but for the given bound, as a
/// user makes it (topology, set-up, the sweeps, normals), on mesh m reset to
/// the input positions before each repeat.
double timeSodt(sodt::MeshF& m, const std::vector<sodt::MeshF::CoordType>& input, const Options& o,
                double maxDeviationRel, sodt::SodtStats& stats) {
  sodt::SodtParams p;
  p.iterations = o.sweeps;
  p.threads = 1;
  p.maxDeviationRel = maxDeviationRel;
  return bestOf(
      o.repeats, [&] { for (std::size_t i = 0; i < input.size(); ++i) m.vert[i].P() = input[i]; },
      [&] { stats = sodt::SodtSmoother<sodt::MeshF>::Apply(m, p); });
}

void usage() {
  std::fprintf(stderr,
               "usage: sodt_openmesh_compare MESH.ply|.off [--sweeps 20] [--repeats 3]\n"
               "  CPU ms per sweep, best of the repeats, one thread: OpenMesh's JacobiLaplaceSmootherT\n"
               "  (tangential, C1), sodt smooth's defaults, and the same with --max-deviation 0\n");
}

}  // namespace

int main(int argc, char** argv) {
  Options o;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if ((a == "--sweeps" || a == "--repeats") && i + 1 < argc) {
      (a == "--sweeps" ? o.sweeps : o.repeats) = std::atoi(argv[++i]);
    } else if (a == "-h" || a == "--help") {
      usage();
      return 0;
    } else if (!a.empty() && a[0] != '-' && o.mesh.empty()) {
      o.mesh = a;
    } else {
      usage();
      return 2;
    }
  }
  if (o.mesh.empty() || o.sweeps < 1 || o.repeats < 1) {
    usage();
    return 2;
  }

  OMesh om;
  if (!OpenMesh::IO::read_mesh(om, o.mesh)) {
    std::fprintf(stderr, "error: OpenMesh cannot read %s\n", o.mesh.c_str());
    return 1;
  }
  sodt::MeshF m;
  const int err = endsWith(o.mesh, ".off") ? vcg::tri::io::ImporterOFF<sodt::MeshF>::Open(m, o.mesh.c_str())
                                           : vcg::tri::io::ImporterPLY<sodt::MeshF>::Open(m, o.mesh.c_str());
  if (err != 0) {
    std::fprintf(stderr, "error: cannot read %s (vcg error %d)\n", o.mesh.c_str(), err);
    return 1;
  }
  vcg::tri::UpdateBounding<sodt::MeshF>::Box(m);

  // OpenMesh: the smoother as its documentation sets it up, on every vertex
  // (its default leaves border vertices fixed), the input restored each time.
  std::vector<OMesh::Point> omInput;
  for (const auto vh : om.vertices()) omInput.push_back(om.point(vh));
  om.request_vertex_normals();
  om.request_face_normals();
  const double omMs = bestOf(
      o.repeats,
      [&] {
        for (const auto vh : om.vertices()) om.set_point(vh, omInput[vh.idx()]);
      },
      [&] {
        OpenMesh::Smoother::JacobiLaplaceSmootherT<OMesh> smoother(om);
        smoother.initialize(OpenMesh::Smoother::SmootherT<OMesh>::Tangential,
                            OpenMesh::Smoother::SmootherT<OMesh>::C1);
        smoother.smooth(static_cast<unsigned int>(o.sweeps));
      });

  std::vector<sodt::MeshF::CoordType> input;
  for (const auto& v : m.vert) input.push_back(v.cP());
  sodt::SodtStats bounded, unbounded;
  const double defMs = timeSodt(m, input, o, sodt::SodtParams{}.maxDeviationRel, bounded);
  const double zeroMs = timeSodt(m, input, o, 0.0, unbounded);

  const double s = o.sweeps;
  const std::string name = o.mesh.substr(o.mesh.find_last_of('/') + 1);  // npos + 1 == 0
  std::printf("%s: %d vertices, %d faces; %d sweeps, CPU time, best of %d, 1 thread\n\n", name.c_str(), m.vn, m.fn,
              o.sweeps, o.repeats);
  std::printf("| method | ms/sweep | x OpenMesh | x sodt --max-deviation 0 |\n|---|---:|---:|---:|\n");
  const auto row = [&](const char* name, double ms) {
    std::printf("| %s | %.1f | %.2f | %.2f |\n", name, ms / s, ms / omMs, ms / zeroMs);
  };
  row("OpenMesh JacobiLaplaceSmootherT, tangential, C1", omMs);
  row("sodt smooth (defaults: guard quality, max deviation 0.1%)", defMs);
  row("sodt smooth --max-deviation 0", zeroMs);
  for (const auto& run : {std::make_pair("defaults", &bounded), std::make_pair("--max-deviation 0", &unbounded)}) {
    const sodt::SodtStats& st = *run.second;
    std::printf("\nsodt %s: %lld visits moved, %lld rejected; deviation points %lld queried, %lld from margins", run.first,
                st.moved + st.backtracked + st.fallbackMoves, st.rejected, st.deviationQueries, st.deviationReused);
  }
  std::printf("\n");
  return 0;
}
