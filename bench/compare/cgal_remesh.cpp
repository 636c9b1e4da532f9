// SPDX-License-Identifier: GPL-3.0-or-later
// sodt_cgal_remesh: CGAL 5.5's remeshers on one mesh, for the comparison of
// bench/compare (sodt_compare runs it as a child process, like meshlabserver).
//
//   sodt_cgal_remesh isotropic IN OUT --target L [--iterations N] [--feature-angle DEG]
//   sodt_cgal_remesh degenerate IN OUT [--feature-angle DEG]
//
// isotropic: Polygon_mesh_processing::isotropic_remeshing of every face to
// the target edge length, N iterations (default 1, CGAL's), the edges whose
// faces turn by more than the feature angle (default 30) constrained (kept
// as chains: split and collapsed along themselves, never flipped).
// degenerate: Polygon_mesh_processing::experimental::
// remove_almost_degenerate_faces with CGAL's definitions: a cap has an angle
// above 160 degrees, a needle a longest / shortest edge ratio above 4; no
// limit on the length of a collapsed edge; the same feature edges
// constrained.
// Prints "seconds S" (the remesher alone, no I/O) on stdout. Exit status: 0
// done, 1 unreadable input, not a triangle mesh CGAL can remesh, or write
// failure, 2 bad command line.

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Polygon_mesh_processing/detect_features.h>
#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/Polygon_mesh_processing/repair_degeneracies.h>
#include <CGAL/Polygon_mesh_processing/triangulate_faces.h>
#include <CGAL/Surface_mesh.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>
#include <string>

namespace {

using Kernel = CGAL::Exact_predicates_inexact_constructions_kernel;
using Mesh = CGAL::Surface_mesh<Kernel::Point_3>;
namespace PMP = CGAL::Polygon_mesh_processing;

int usage(const char* why) {
  std::fprintf(stderr,
               "sodt_cgal_remesh: %s\n"
               "usage: sodt_cgal_remesh isotropic IN OUT --target L [--iterations N] [--feature-angle DEG]\n"
               "       sodt_cgal_remesh degenerate IN OUT [--feature-angle DEG]\n",
               why);
  return 2;
}

/// A positive finite number, or throws std::invalid_argument naming the option.
double positive(const std::string& option, const char* text) {
  char* end = nullptr;
  const double x = std::strtod(text, &end);
  if (end == text || *end != '\0' || !std::isfinite(x) || !(x > 0))
    throw std::invalid_argument(option + " needs a positive number, not '" + text + "'");
  return x;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) return usage("a mode, IN and OUT are required");
  const std::string mode = argv[1], in = argv[2], out = argv[3];
  if (mode != "isotropic" && mode != "degenerate") return usage(("unknown mode '" + mode + "'").c_str());
  double target = 0, featureDeg = 30;
  unsigned iterations = 1;
  try {
    for (int i = 4; i < argc; ++i) {
      const std::string o = argv[i];
      if (i + 1 >= argc) return usage((o + " needs a value").c_str());
      if (o == "--target")
        target = positive(o, argv[++i]);
      else if (o == "--feature-angle")
        featureDeg = positive(o, argv[++i]);
      else if (o == "--iterations")
        iterations = static_cast<unsigned>(positive(o, argv[++i]));
      else
        return usage(("unknown option '" + o + "'").c_str());
    }
  } catch (const std::invalid_argument& e) {
    return usage(e.what());
  }
  if (mode == "isotropic" && !(target > 0)) return usage("isotropic needs --target");

  Mesh mesh;
  if (!CGAL::IO::read_polygon_mesh(in, mesh) || mesh.number_of_faces() == 0) {
    std::fprintf(stderr, "sodt_cgal_remesh: cannot read a polygon mesh from %s\n", in.c_str());
    return 1;
  }
  if (!CGAL::is_triangle_mesh(mesh)) PMP::triangulate_faces(mesh);
  auto feature = mesh.add_property_map<Mesh::Edge_index, bool>("e:feature", false).first;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    PMP::detect_sharp_edges(mesh, featureDeg, feature);
    if (mode == "isotropic") {
      PMP::isotropic_remeshing(faces(mesh), target, mesh,
                               PMP::parameters::number_of_iterations(iterations).edge_is_constrained_map(feature));
    } else {
      const double capCos = std::cos(160.0 * CGAL_PI / 180.0);
      PMP::experimental::remove_almost_degenerate_faces(mesh, capCos, 4.0, 0.0,
                                                        PMP::parameters::edge_is_constrained_map(feature));
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sodt_cgal_remesh: CGAL failed on %s: %s\n", in.c_str(), e.what());
    return 1;
  }
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  mesh.collect_garbage();
  if (!CGAL::IO::write_polygon_mesh(out, mesh, CGAL::parameters::stream_precision(17))) {
    std::fprintf(stderr, "sodt_cgal_remesh: cannot write %s\n", out.c_str());
    return 1;
  }
  std::printf("seconds %.6f\n", seconds);
  return 0;
}
