// SPDX-License-Identifier: GPL-3.0-or-later
// Command-line front end: `sodt smooth` runs the S-ODT smoother on a mesh
// file, `sodt classify` writes the smooth/crease/corner classification of its
// vertices, `sodt stats` measures a mesh. The command line is parsed in
// options.cpp, the summaries and reports are written by report.cpp; this file
// runs the commands, with the progress line, signals and exit codes.
#include "options.h"
#include "report.h"

#include <sodt/maths/classify.h>
#include <sodt/denoise/noise_estimate.h>
#include <sodt_io/io.h>
#include <sodt_io/mesh.h>
#include <sodt/params.h>
#include <sodt_io/prebuilt.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <exception>
#include <memory>
#include <stdexcept>
#include <string>
#include <unistd.h>
#include <vector>

#ifndef SODT_VERSION
#define SODT_VERSION "unknown"
#endif

namespace {

using namespace sodt_cli;

// ---------------------------------------------------------------------------
// Interruption and progress on stderr

// Temporary output files, removed by the signal handler: an interrupted run
// leaves OUT and the report as they were. Fixed storage, no allocation in
// the handler.
constexpr int kMaxTemps = 4;
constexpr std::size_t kTempPathMax = 4096;
char gTempPath[kMaxTemps][kTempPathMax];
volatile std::sig_atomic_t gTempActive[kMaxTemps];

/// Lets the signal handler remove f's temporary file (until the process ends).
void trackTemporary(const sodt::PendingFile& f) {
  if (f.direct()) return;  // a device or FIFO written in place: never removed
  const std::string& p = f.tempPath();
  if (p.size() >= kTempPathMax) return;
  for (int i = 0; i < kMaxTemps; ++i)
    if (!gTempActive[i]) {
      std::memcpy(gTempPath[i], p.c_str(), p.size() + 1);
      std::atomic_signal_fence(std::memory_order_seq_cst);  // path complete before the flag
      gTempActive[i] = 1;
      return;
    }
}

/// SIGINT/SIGTERM/SIGHUP: remove the temporary files, then die of the signal.
extern "C" void onSignal(int sig) {
  for (int i = 0; i < kMaxTemps; ++i)
    if (gTempActive[i]) ::unlink(gTempPath[i]);
  static const char msg[] = "\nsodt: interrupted\n";
  const ssize_t n = ::write(STDERR_FILENO, msg, sizeof msg - 1);
  (void)n;
  std::signal(sig, SIG_DFL);
  std::raise(sig);
}

/// One status line on stderr, redrawn with '\r'; only used on a terminal.
struct StatusLine {
  bool enabled = false;
  bool open = false;
  std::size_t width = 0;
  std::string last;

  void draw(const std::string& text) {
    if (!enabled || (open && text == last)) return;
    std::string s = "\r" + text;
    if (text.size() < width) s.append(width - text.size(), ' ');
    std::fputs(s.c_str(), stderr);
    std::fflush(stderr);
    width = std::max(width, text.size());
    last = text;
    open = true;
  }
  /// Keeps the line (newline) or wipes it.
  void end(bool keep) {
    if (!open) return;
    if (keep)
      std::fputc('\n', stderr);
    else
      std::fprintf(stderr, "\r%*s\r", static_cast<int>(width), "");
    std::fflush(stderr);
    open = false;
    width = 0;
    last.clear();
  }
};

StatusLine gStatus;

/// vcg::CallBackPos for the smoother: draws "[#####     ] 45% S-ODT sweep 9/20".
bool progressCallback(const int pos, const char* msg) {
  if (gStatus.enabled) {
    const int pct = std::min(100, std::max(0, pos));
    const int barWidth = 20;
    const int filled = pct * barWidth / 100;
    char head[64];
    std::snprintf(head, sizeof head, "] %3d%% ", pct);
    gStatus.draw("[" + std::string(filled, '#') + std::string(barWidth - filled, ' ') + head + (msg ? msg : ""));
  }
  return true;
}

std::string baseName(const std::string& p) {
  const std::size_t slash = p.find_last_of('/');
  return slash == std::string::npos ? p : p.substr(slash + 1);
}

/// Loads a mesh for a subcommand, with the status line, and rejects meshes
/// without triangles.
void loadInput(const std::string& path, MeshD& m, sodt::LoadInfo* info) {
  gStatus.draw("loading " + baseName(path) + "...");
  sodt::loadMesh(path, m, info);
  gStatus.end(false);
  if (m.fn == 0) throw sodt::InvalidInput("'" + path + "': no triangles");
}

/// The temporary file behind an output path, removed on a signal; null for
/// no path (an optional output not asked for).
std::unique_ptr<sodt::PendingFile> pendingOutput(const std::string& path) {
  if (path.empty()) return nullptr;
  std::unique_ptr<sodt::PendingFile> f(new sodt::PendingFile(path));
  trackTemporary(*f);
  return f;
}

/// Items joined with sep.
std::string joined(const std::vector<std::string>& items, const char* sep) {
  std::string s;
  for (const std::string& item : items) s += (s.empty() ? "" : sep) + item;
  return s;
}

/// Warns, a line each, of what OUT does not keep of the input: what the
/// loader did not read, and what OUT's format has no place for.
void warnNotKept(const SmoothOptions& o, const MeshD& m, const sodt::LoadInfo& info, const sodt::SaveOptions& so) {
  if (!info.dropped.empty())
    std::fprintf(stderr, "sodt: warning: '%s' holds what sodt does not read, so '%s' does not have it: %s\n",
                 o.in.c_str(), o.out.c_str(), joined(info.dropped, "; ").c_str());
  const std::vector<std::string> lost = sodt::notKept(o.out, m, so);
  if (!lost.empty())
    std::fprintf(stderr, "sodt: warning: '%s' does not keep the input's %s: its format has no place for them\n",
                 o.out.c_str(), joined(lost, ", ").c_str());
}

int runSmooth(const SmoothOptions& o) {
  gStatus.enabled = gStatus.enabled && !o.quiet;

  // Create the temporary outputs first: an unwritable destination fails
  // before any work, and anything that fails later removes them.
  const std::unique_ptr<sodt::PendingFile> out = pendingOutput(o.out);
  const std::unique_ptr<sodt::PendingFile> report = pendingOutput(o.report);
  const std::unique_ptr<sodt::PendingFile> classesOut = pendingOutput(o.classesOut);

  MeshD m;
  sodt::LoadInfo info;
  loadInput(o.in, m, &info);
  if (o.params.selectedOnly && info.selectedVertices == 0)
    throw sodt::InvalidInput("'" + o.in + "': --selected-only, but no vertex of the input is selected "
                             "(a PLY 'flags' property with the selection bit; MeshLab: export with Flags)");

  SmoothResult r;
  gStatus.draw("measuring input...");
  r.before = measure(m, sodt::resolveThreads(o.params.threads));
  // Not a copy of the mesh: with the smoother's working memory that would
  // more than double the peak on a large mesh.
  InputGeometry input = keepInput(m, o.params.flips || o.params.repair);
  gStatus.end(false);

  progressCallback(0, ("S-ODT sweep 0/" + std::to_string(o.params.iterations)).c_str());
  const auto t0 = std::chrono::steady_clock::now();
  r.stats = sodt::SodtSmoother<MeshD>::Apply(m, o.params, &progressCallback, &r.classes);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  gStatus.end(true);
  const sodt::SodtStats& st = r.stats;
  if (st.cancelled) throw std::runtime_error("smoothing was cancelled");

  gStatus.draw("measuring output...");
  r.after = measure(m, st.threads);
  if (o.params.repair) r.corners = sodt::protectedAngles(m, o.params.featureAngleDeg, o.params.repairAngleDeg);
  {
    sodt::SampleMesh ref;  // freed before the save, which reads OUT back
    rebuildInput(input, m, ref, st.reorientedFaces > 0);
    if (o.distance)
      r.distance = distanceTo(m, ref, st.threads);
    else
      r.distance.measured = false;
    // Face by face while the faces correspond, else each face against the
    // input face under it.
    r.inverted = sodt::countInvertedFaces(m, ref, st.threads, &r.invertedFaceByFace);
  }
  gStatus.end(false);

  gStatus.draw("writing " + baseName(o.out) + "...");
  sodt::SaveOptions so;
  so.vertexQuality = info.vertexQuality;
  so.vertexColor = info.vertexColor;
  so.vertexSelection = info.vertexSelection;
  so.vertexNormals = info.vertexNormals;  // the core recomputed them for the new positions
  // Each vertex carries its texture coordinates as it slides; the core
  // interpolates them for the vertices the repair adds.
  so.vertexTexCoords = info.vertexTexCoords;
  sodt::saveMesh(*out, m, so);
  if (report) sodt::writeText(*report, smoothReport(o, m, r));
  if (classesOut) {
    gStatus.draw("writing " + baseName(o.classesOut) + "...");
    saveClassMesh(*classesOut, m, r.classes);  // after OUT: replaces m's quality and colour
  }
  gStatus.end(false);
  out->commit();
  if (classesOut) classesOut->commit();
  if (report) report->commit();

  if (!o.quiet) printSmoothSummary(o, m, r);
  if (!o.quiet) warnNotKept(o, m, info, so);
  if (!o.quiet && info.weldedCorners > 0)
    std::printf("  STL input      %lld corners with equal coordinates welded into %d vertices\n",
                info.weldedCorners + m.vn, m.vn);
  if (!o.quiet && st.fixedNonManifold > 0)
    std::fprintf(stderr,
                 "sodt: warning: %d vertices stayed fixed: their faces are non-manifold (an edge with three or "
                 "more faces, a pinch) or cannot be given one winding (a Moebius band)\n",
                 st.fixedNonManifold);
  if (!o.quiet && o.params.algorithm == sodt::Algorithm::Denoise && r.before.noiseEdges < sodt::kLittleNoiseEdges)
    std::fprintf(stderr,
                 "sodt: warning: the input looks nearly noise-free (noise estimated at %.3f mean edges): denoise "
                 "removes noise, and on a clean mesh it mostly smooths the shape; 'feature' improves the "
                 "triangles and keeps the surface\n",
                 r.before.noiseEdges);
  // Filtered scores its filters against the noise and mostly applies none
  // to a clean mesh; it warns when it filtered one all the same.
  if (!o.quiet && o.params.algorithm == sodt::Algorithm::Filtered && st.filter.kind != sodt::FilterKind::None &&
      st.filter.noiseEdges < sodt::kLittleNoiseEdges)
    std::fprintf(stderr,
                 "sodt: warning: the input looks nearly noise-free (noise estimated at %.3f mean edges) but "
                 "filtering still scored better (%s); on a clean mesh that mostly smooths the shape: 'feature' "
                 "improves the triangles and keeps the surface, or set --noise-level\n",
                 st.filter.noiseEdges, sodt::describeFilter(st.filter).c_str());
  return kExitOk;
}

int runStats(const StatsOptions& o) {
  const std::unique_ptr<sodt::PendingFile> jsonOut = pendingOutput(o.json);
  MeshD m;
  loadInput(o.in, m, nullptr);
  MeshD ref;
  if (!o.reference.empty()) loadInput(o.reference, ref, nullptr);

  gStatus.draw("measuring...");
  const std::string text = statsReport(o, m, o.reference.empty() ? nullptr : &ref, sodt::resolveThreads(0));
  gStatus.end(false);

  if (jsonOut) {
    sodt::writeText(*jsonOut, text);
    jsonOut->commit();
  } else if (std::fwrite(text.data(), 1, text.size(), stdout) != text.size() || std::fflush(stdout) != 0) {
    throw sodt::IoError(std::string("cannot write to standard output: ") + std::strerror(errno));
  }
  return kExitOk;
}

int runClassify(const ClassifyOptions& o) {
  const std::unique_ptr<sodt::PendingFile> out = pendingOutput(o.out);
  const std::unique_ptr<sodt::PendingFile> jsonOut = pendingOutput(o.json);

  MeshD m;
  loadInput(o.in, m, nullptr);
  gStatus.draw("classifying...");
  const sodt::Classification cls = sodt::classifyVertices(m, o.params.epsilon, o.params.eta);
  gStatus.end(false);

  gStatus.draw("writing " + baseName(o.out) + "...");
  saveClassMesh(*out, m, cls);
  if (jsonOut) sodt::writeText(*jsonOut, classifyReport(o, m, cls));
  gStatus.end(false);
  out->commit();
  if (jsonOut) jsonOut->commit();

  printClassifySummary(o, m, cls);
  return kExitOk;
}

int run(const std::vector<std::string>& args) {
  CommandLine cl;
  switch (cl.parse(args)) {
    case Command::Done: return kExitOk;
    case Command::Version: std::printf("sodt %s\n", SODT_VERSION); return kExitOk;
    case Command::Smooth: return runSmooth(cl.smooth);
    case Command::Classify: return runClassify(cl.classify);
    case Command::Stats: return runStats(cl.stats);
  }
  return kExitFailure;
}

}  // namespace

/// Entry point: every error ends as one "sodt: error: ..." line on stderr and
/// a non-zero exit status (see `sodt --help`).
int main(int argc, char** argv) {
  // A signal the caller ignores stays ignored (nohup, `cmd &` in a
  // non-interactive shell): only the others clean up and end the run.
  for (int sig : {SIGINT, SIGTERM, SIGHUP})
    if (std::signal(sig, onSignal) == SIG_IGN) std::signal(sig, SIG_IGN);
  gStatus.enabled = ::isatty(STDERR_FILENO) == 1;
  const std::vector<std::string> args(argv + 1, argv + argc);
  try {
    return run(args);
  } catch (const UsageError& e) {
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: %s (see '%s')\n", e.what(), e.helpCommand.c_str());
    return kExitUsage;
  } catch (const std::bad_alloc&) {
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: out of memory\n");
    return kExitFailure;
  } catch (const std::exception& e) {
    // sodt::InvalidInput, sodt::IoError and vcglib's exceptions.
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: %s\n", e.what());
    return kExitFailure;
  } catch (...) {
    gStatus.end(false);
    std::fprintf(stderr, "sodt: error: unexpected failure\n");
    return kExitFailure;
  }
}
