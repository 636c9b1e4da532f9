// SPDX-License-Identifier: GPL-3.0-or-later
// Markdown report and SVG figures of sodt_compare (see compare.h).
#include "compare.h"

#include "svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <thread>

namespace sodtcmp {

namespace {

/// The processor's model name as /proc/cpuinfo gives it, or "" where there is
/// no such file or line: timings are only comparable on the same processor.
std::string processorName() {
  std::ifstream in("/proc/cpuinfo");
  std::string line;
  while (std::getline(in, line)) {
    if (line.compare(0, 10, "model name") != 0) continue;
    const std::size_t colon = line.find(':');
    if (colon == std::string::npos) break;
    const std::size_t first = line.find_first_not_of(" \t", colon + 1);
    return first == std::string::npos ? std::string() : line.substr(first);
  }
  return std::string();
}

}  // namespace

// ---------------------------------------------------------------------------
// The paper's Tables 3 and 4

const std::vector<PaperRow>& paperTables() {
  // Table 3 (min angle: original, S-ODT with 20 iterations, Ohtake's) and
  // Table 4 (vertices, running time in seconds on a 2.0 GHz Pentium IV:
  // S-ODT, Ohtake's, Sun's), as printed in the paper.
  static const std::vector<PaperRow> rows = {
      {"dancer", 0.8, 18.3, "Alg.1", 0.4, 24998, 12.0, 3.3, 0.8},
      {"elephant", 1.4, 17.9, "Alg.1", 0.2, 52099, 16.6, 7.6, 1.0},
      {"bimba", 1.4, 15.5, "Alg.1", 0.2, 83887, 24.5, 11.8, 1.7},
      {"RyR", 4.9, 17.3, "Alg.1", 0.2, 129346, 35.8, 16.8, 2.6},
      {"noise-free fandisk", 0.0, 17.7, "Alg.2", 0.1, 6475, 4.5, 2.0, 0.1},
      {"noisy fandisk", 16.0, 18.4, "Alg.3", 0.4, 6475, 6.3, 3.0, 0.1},
      {"Chinese lion", 0.2, 16.8, "Alg.3", 0.0, 99289, 49.8, 13.0, 2.1},
      {"dragon head", 0.3, 17.5, "Alg.3", 0.1, 99777, 50.5, 14.8, 3.1},
      {"venus", 1.0, 16.8, "Alg.3", 0.0, 100759, 53.3, 15.7, 8.8},
      {"angel", 0.1, 16.3, "Alg.3", 0.0, 236979, 120.4, 35.1, 15.7},
  };
  return rows;
}

const PaperRow* findPaperRow(const std::string& model) {
  for (const PaperRow& r : paperTables())
    if (model == r.model) return &r;
  return nullptr;
}

namespace {

const char* kCitation =
    "Z. Gao, Z. Yu, M. Holst, *Feature-preserving surface mesh smoothing via suboptimal Delaunay "
    "triangulation*, Graphical Models 75(1):23-38, 2013, doi:10.1016/j.gmod.2012.10.007 (Section 3; text in "
    "`../shared/paper/sodt-paper.txt` next to the checkout)";

std::string variantId(sodt::Algorithm a) {
  switch (a) {
    case sodt::Algorithm::Feature: return "sodt_feature";
    case sodt::Algorithm::Denoise: return "sodt_denoise";
    default: return "sodt_basic";
  }
}

std::string f1(double v) {
  if (v != v) return "n/a";
  char b[32];
  std::snprintf(b, sizeof b, "%.1f", v);
  return b;
}

std::string f2(double v) {
  if (v != v) return "n/a";
  char b[32];
  std::snprintf(b, sizeof b, "%.2f", v);
  return b;
}

/// Percent with 3 significant digits.
std::string pct3(double rel) {
  if (rel != rel) return "n/a";
  if (std::isinf(rel)) return "inf";
  if (std::abs(100.0 * rel) < 1e-4) return rel == 0 ? "0" : "< 0.0001";
  return formatG(100.0 * rel, 3);
}

std::string seconds(double s) {
  if (s != s) return "n/a";
  char b[32];
  if (s < 0.1)
    std::snprintf(b, sizeof b, "%.3f", s);
  else if (s < 10)
    std::snprintf(b, sizeof b, "%.2f", s);
  else
    std::snprintf(b, sizeof b, "%.1f", s);
  return b;
}

std::string invertedText(long long n) {
  if (n == -1) return "other connectivity";
  if (n < -1) return "–";
  return std::to_string(n);
}

std::string volumeText(const Metrics& m, const Metrics& input) {
  if (!input.closed) return "open input";
  if (!m.closed) return "not closed";
  if (m.volumeChange != m.volumeChange) return "n/a";
  return formatG(100.0 * m.volumeChange, 2);
}

/// Built-in vertex-moving filters (same connectivity), the set the claim is about.
bool isSmootherRow(const Row& r) { return r.method.kind == Kind::Builtin && r.method.smoother && r.m.ok; }

/// Hausdorff values within 1e-6 of the diagonal count as equal (sampling noise).
bool hausNoLarger(double a, double b) { return a <= b + 1e-6; }

std::string methodsLine(const std::vector<std::string>& names) {
  std::string s;
  for (std::size_t i = 0; i < names.size(); ++i) s += (i ? ", " : "") + names[i];
  return s.empty() ? "none" : s;
}

std::string shortLabel(const Method& m) {
  std::string s = m.label;
  const std::string ml = "MeshLab ";
  if (s.compare(0, ml.size(), ml) == 0) s = s.substr(ml.size());
  return s;
}

void perMeshTable(std::ostringstream& o, const MeshReport& r) {
  const bool ref = !r.job.reference.empty();
  o << "| method | V | F | min ° | max ° | < 30° | p1 tri-min ° | Hausdorff to input (% diag) |";
  if (ref) o << " to reference, max / mean (% diag) |";
  o << " volume change (%) | inverted faces | time (s) |\n";
  o << "|---|--:|--:|--:|--:|--:|--:|--:|";
  if (ref) o << "--:|";
  o << "--:|--:|--:|\n";
  auto line = [&](const std::string& label, const Metrics& m, const std::string& time) {
    o << "| " << label << " | " << m.vertices << " | " << m.faces << " | " << f2(m.minDeg) << " | " << f2(m.maxDeg)
      << " | " << f1(100.0 * m.fracBelow30) << "% | " << f2(m.p1TriMinDeg) << " | " << pct3(m.hausInput) << " |";
    if (ref) o << " " << pct3(m.hausRef) << " / " << pct3(m.meanRef) << " |";
    o << " " << volumeText(m, r.input) << " | " << invertedText(m.inverted) << " | " << time << " |\n";
  };
  line("**input**", r.input, "");
  for (const Row& row : r.rows) {
    if (!row.m.ok) {
      o << "| " << row.method.label << " | failed: " << row.m.error << " |";
      for (int k = 0; k < (ref ? 10 : 9); ++k) o << " |";
      o << "\n";
      continue;
    }
    std::string label = row.method.label;
    if (row.method.algorithm == r.job.variant && row.method.kind == Kind::InProcess &&
        (row.method.id == variantId(r.job.variant)))
      label = "**" + label + "**";
    const std::string t = seconds(row.m.seconds) + (row.method.kind == Kind::InProcess ? "" : " †");
    line(label, row.m, t);
  }
}

/// The headline S-ODT row of a mesh and what it beats.
struct Claim {
  const Row* sodt = nullptr;
  std::vector<std::string> beaten, notBeaten, largerH;
};

Claim claimOf(const MeshReport& r) {
  Claim c;
  c.sodt = r.row(variantId(r.job.variant));
  if (!c.sodt || !c.sodt->m.ok) return c;
  for (const Row& row : r.rows) {
    if (!isSmootherRow(row)) continue;
    if (!hausNoLarger(row.m.hausInput, c.sodt->m.hausInput))
      c.largerH.push_back(shortLabel(row.method));
    else if (c.sodt->m.minDeg > row.m.minDeg)
      c.beaten.push_back(shortLabel(row.method));
    else
      c.notBeaten.push_back(shortLabel(row.method));
  }
  return c;
}

}  // namespace

RepairVerdict repairVerdict(const MeshReport& r) {
  RepairVerdict v;
  auto okRow = [&](const std::string& id) -> const Row* {
    const Row* row = r.row(id);
    return row && row->m.ok ? row : nullptr;
  };
  v.repair = okRow("sodt_flips_repair");
  v.flipsOnly = okRow("sodt_flips");
  v.isotropic = okRow("ml_isotropic_edge");
  v.planarFlip = okRow("ml_planar_flip");
  if (v.repair && v.repair->m.verticesAdded >= 0)
    v.repairChanged = v.repair->m.verticesAdded + v.repair->m.verticesRemoved;
  if (v.isotropic) v.isotropicChanged = std::llabs(v.isotropic->m.vertices - r.input.vertices);
  v.comparable = v.repairChanged >= 0 && v.isotropic;
  if (!v.comparable) return v;
  v.largerMinAngle = v.repair->m.minDeg > v.isotropic->m.minDeg;
  v.noLargerHausdorff = hausNoLarger(v.repair->m.hausInput, v.isotropic->m.hausInput);
  // Against a lower bound of the remesher's changes: "fewer" holds for sure.
  v.fewerVertexChanges = v.repairChanged < v.isotropicChanged;
  return v;
}

const std::vector<std::string>& repairPeers() {
  static const std::vector<std::string> peers = {"ml_isotropic_edge", "ml_isotropic_edge_dist", "cgal_isotropic_edge",
                                                 "cgal_degenerate"};
  return peers;
}

PeerVerdict peerVerdict(const Row* repair, const Row* peer) {
  if (!repair || !peer || !repair->m.ok || !peer->m.ok) return PeerVerdict::NotRun;
  if (repair->m.minDeg > peer->m.minDeg)
    return hausNoLarger(repair->m.hausInput, peer->m.hausInput) ? PeerVerdict::Beats : PeerVerdict::LargerDistance;
  return hausNoLarger(peer->m.hausInput, repair->m.hausInput) ? PeerVerdict::Loses : PeerVerdict::PeerMovesFurther;
}

namespace {

/// A peer verdict in a table cell.
const char* peerVerdictText(PeerVerdict v) {
  switch (v) {
    case PeerVerdict::Beats: return "**beats**";
    case PeerVerdict::LargerDistance: return "larger min angle, but farther from the input";
    case PeerVerdict::PeerMovesFurther: return "peer's min angle no smaller, but it moves farther";
    case PeerVerdict::Loses: return "**loses**";
    case PeerVerdict::NotRun: break;
  }
  return "n/a";
}

/// "min ° / Hausdorff % / needles + caps / V" of a row, or why it did not run.
std::string peerCell(const Row* row) {
  if (!row) return "not run";
  if (!row->m.ok) return "failed: " + row->m.error;
  return f2(row->m.minDeg) + " / " + pct3(row->m.hausInput) + " / " + std::to_string(row->m.needles) + " + " +
         std::to_string(row->m.caps) + " / " + std::to_string(row->m.vertices);
}

/// The repair against every peer that changes the connectivity, CGAL's
/// included, with the needles and caps by CGAL's definitions.
void peerTable(std::ostringstream& o, const std::vector<MeshReport>& reports) {
  o << "### Against every remesher\n\n";
  o << "Each cell: min ° / Hausdorff % / needles + caps (CGAL's definitions: longest / shortest edge >= 4; an "
       "angle >= 160°) / output vertices. The peers: MeshLab's isotropic explicit remeshing at the input's mean "
       "edge length, without and with its surface-distance check at S-ODT's deviation bound (0.1% of the "
       "diagonal); CGAL 5.5's `isotropic_remeshing` at the mean edge length with as many iterations as S-ODT's "
       "sweeps, and `experimental::remove_almost_degenerate_faces` (caps above 160°, needles above 4, no limit on "
       "the length of a collapsed edge), both with the edges sharper than 30° constrained (`detect_sharp_edges`; "
       "run by `sodt_cgal_remesh`, time: the remesher alone). The verdict under each peer: the repair **beats** it "
       "with a larger minimum angle at a Hausdorff distance no larger; otherwise the cell says which of the two "
       "fails.\n\n";
  o << "| mesh | + repair |";
  const std::vector<std::string>& peers = repairPeers();
  for (const std::string& id : peers) o << " " << findMethod(id)->label << " | verdict |";
  o << "\n|---|---|";
  for (std::size_t i = 0; i < peers.size(); ++i) o << "---|---|";
  o << "\n";
  std::vector<std::string> notBeaten;
  int meshes = 0, beatAll = 0;
  for (const MeshReport& r : reports) {
    const Row* repair = r.row("sodt_flips_repair");
    if (!repair || !repair->m.ok) continue;
    ++meshes;
    bool all = true;
    o << "| " << r.job.name << " | " << peerCell(repair) << " |";
    for (const std::string& id : peers) {
      const Row* peer = r.row(id);
      const PeerVerdict v = peerVerdict(repair, peer);
      o << " " << peerCell(peer) << " | " << peerVerdictText(v) << " |";
      if (v != PeerVerdict::Beats) {
        all = false;
        notBeaten.push_back(r.job.name + " against " + findMethod(id)->label + " (" + peerVerdictText(v) + ")");
      }
    }
    o << "\n";
    if (all) ++beatAll;
  }
  o << "\n**Measured:** the local repair beats every peer on " << beatAll << " of " << meshes << " meshes.";
  if (!notBeaten.empty()) {
    o << " Where it does not: ";
    for (std::size_t i = 0; i < notBeaten.size(); ++i) o << (i ? "; " : "") << notBeaten[i];
    o << ".";
  }
  o << "\n\n";
}

/// "min ° / Hausdorff %" of a row, or n/a.
std::string minAndHaus(const Row* row) {
  return row ? f2(row->m.minDeg) + " / " + pct3(row->m.hausInput) : std::string("n/a");
}

/// Why the repair does not beat the remeshing (empty: it does).
std::string verdictText(const RepairVerdict& v) {
  if (!v.comparable) return "n/a";
  std::vector<std::string> no;
  if (!v.largerMinAngle) no.push_back("min angle not larger");
  if (!v.noLargerHausdorff) no.push_back("larger Hausdorff");
  if (!v.fewerVertexChanges) no.push_back("not fewer vertices changed");
  return no.empty() ? std::string("**yes**") : "no: " + methodsLine(no);
}

/// The section on S-ODT with flips and local repair against MeshLab's
/// connectivity-changing methods (nothing when no repair row ran).
void repairSection(std::ostringstream& o, const std::vector<MeshReport>& reports) {
  bool any = false;
  for (const MeshReport& r : reports) any = any || repairVerdict(r).repair;
  if (!any) return;
  o << "## Local repair against remeshing\n\n";
  o << "The headline S-ODT variant with flips, and with flips and the local repair (the in-process rows "
       "\"+ flips\" and \"+ flips + repair\" of the per-mesh tables), against the MeshLab methods that change "
       "the connectivity as well: isotropic explicit remeshing at the input's mean edge length (feature angle "
       "30°) and planar flipping. Every method moves vertices; \"vertices changed\" counts the vertices a "
       "method adds or removes. It is exact for the repair (vertices added + removed, from the smoother's "
       "statistics `SodtStats::verticesAdded` and `verticesRemoved`). For the remesher it is |V_out − V_in|, a "
       "lower bound: the remesher resamples the whole surface, and its splits and collapses cancel in the count. "
       "Planar flipping keeps the vertex set. \"Repair beats remeshing\": a larger minimum angle, a Hausdorff "
       "distance to the input no larger (within 1e-6 of the diagonal), and fewer vertices changed than the "
       "remesher's lower bound.\n\n";
  o << "| mesh | V | input min ° | S-ODT variant + flips: min ° / Hausdorff % | + repair: min ° / Hausdorff % | "
       "repair: V out (added / removed) | repair: triangles left below target | isotropic, mean edge: min ° / "
       "Hausdorff % | isotropic: V out (\\|V_out − V_in\\|, a lower bound) | planar flipping: min ° / "
       "Hausdorff % | repair beats remeshing |\n";
  o << "|---|--:|--:|---|---|---|--:|---|---|---|---|\n";
  int meshes = 0, beats = 0, gained = 0, withFlips = 0;
  std::vector<std::string> beaten, notBeaten;
  for (const MeshReport& r : reports) {
    const RepairVerdict v = repairVerdict(r);
    if (!v.repair) continue;
    ++meshes;
    o << "| " << r.job.name << " | " << r.input.vertices << " | " << f2(r.input.minDeg) << " | "
      << sodt::toString(r.job.variant) << ": " << minAndHaus(v.flipsOnly) << " | " << minAndHaus(v.repair) << " | "
      << v.repair->m.vertices << " (+" << v.repair->m.verticesAdded << " / −" << v.repair->m.verticesRemoved
      << ") | " << v.repair->m.belowRepairTarget << " | " << minAndHaus(v.isotropic) << " | ";
    if (v.isotropic)
      o << v.isotropic->m.vertices << " (" << v.isotropicChanged << ")";
    else
      o << "n/a";
    o << " | " << minAndHaus(v.planarFlip) << " | " << verdictText(v) << " |\n";
    if (v.beats()) {
      ++beats;
      beaten.push_back(r.job.name);
    } else {
      notBeaten.push_back(r.job.name + " (" + verdictText(v) + ")");
    }
    if (v.flipsOnly) {
      ++withFlips;
      if (v.repair->m.minDeg > v.flipsOnly->m.minDeg) ++gained;
    }
  }
  o << "\n**Measured:** the local repair beats the isotropic remeshing (target = mean edge) on " << beats << " of "
    << meshes << " meshes" << (beaten.empty() ? "" : " (" + methodsLine(beaten) + ")");
  for (std::size_t i = 0; i < notBeaten.size(); ++i) o << (i ? "; " : "; not on ") << notBeaten[i];
  o << ".";
  if (withFlips > 0)
    o << " It raised the minimum angle over flips alone on " << gained << " of " << withFlips << " meshes.";
  o << "\n\n";
  peerTable(o, reports);
}

}  // namespace

std::string histogramFile(const MeshReport& r) { return r.job.name + "_angles.svg"; }
std::string convergenceFile(const MeshReport& r) { return r.job.name + "_convergence.svg"; }

// ---------------------------------------------------------------------------
// Markdown

std::string markdownReport(const std::vector<MeshReport>& reports, const Options& opt, const std::string& commandLine,
                           const std::string& meshlabLine, const std::string& figDir) {
  std::ostringstream o;
  const int N = opt.iterations;
  o << "# S-ODT compared with the numerical ODT and MeshLab's built-in smoothers\n\n";
  o << "<!-- Generated by sodt_compare (bench/compare). Do not edit: rerun the command below. -->\n\n";
  o << "Generated from a fresh build by one command (from the repository root; the shared meshes are the "
       "folder `../shared/meshes` next to the checkout):\n\n";
  o << "```sh\ncmake -S . -B build && cmake --build build -j2 --target sodt_compare\n" << commandLine << "\n```\n\n";
  o << "`sodt_compare` builds the S-ODT plugin first (a target dependency), runs every method on the same input, "
       "measures every output with the core's metrics (`vcg_core/sodt_io/metrics.h`) and writes this file and the "
       "SVG figures in `"
    << figDir << "/`. Meshes, `.mlx` scripts and meshlabserver logs go to the work folder (`--work`).\n\n";

  // --- Setup
  o << "## Setup\n\n";
  o << "* **Same input, same step count.** Every method starts from the same file. The S-ODT variants, the "
       "numerical ODT and the Laplacian reference run "
    << N
    << " Gauss-Seidel sweeps in this process (`sodt::SodtSmoother<sodt::MeshD>`, double precision) on one thread "
       "(`threads` = 1; the library default 0 would use every core) with the library's other "
       "defaults (`sodt::SodtParams{}`): guard `quality` (no fold, a vertex star's smallest angle may not "
       "decrease), Laplacian fallback on, moves of basic/feature/ODT/Laplacian bounded to 0.1 % of the diagonal "
       "from the input surface. So S-ODT, ODT and Laplacian differ only in the target of each vertex move. "
       "MeshLab filters get "
    << N
    << " where they have a step count (Laplacian, Taubin, TwoStep: `stepSmoothNum`; surface-preserving Laplacian: "
       "`iterations`; isotropic remeshing: `Iterations`), their defaults otherwise (table below).\n";
  o << "* **Numerical ODT.** `Algorithm::Odt` minimises Eq. 3 (true areas S'_k) per vertex in its tangent plane "
       "by damped Newton iterations in 2 variables (analytic gradient, finite-difference Hessian, at most 50 "
       "iterations), inside the same Gauss-Seidel sweep and the same guard as S-ODT. The paper instead solved "
       "Eq. 3 with L-BFGS (5 iterations, about 2 min against 36 s for 20 S-ODT iterations on the 129K-vertex RyR "
       "model, Figure 6). Our ODT is therefore a per-vertex exact minimiser, not the paper's global solver, so its "
       "cost ratio to S-ODT compares with the paper's in order of magnitude only (ODT section: timed with the "
       "guards and, as in the paper, without).\n";
  {
    const sodt::SodtParams d;
    o << "* **Flips and local repair.** Two more in-process rows run each mesh's headline variant (the bold row) "
         "with `flips` = true (edge flips between sweeps across edges flatter than "
      << formatG(d.flipMaxDihedralDeg, 3)
      << "°), and with `flips` and `repair` = true (after the sweeps, where a triangle's smallest angle is still "
         "below "
      << formatG(d.repairAngleDeg, 3)
      << "°: edge collapses, splits and flips, none of which flips or collapses a feature edge (one whose faces' "
         "normals differ by more than "
      << formatG(d.featureAngleDeg, 3)
      << "°), and S-ODT relaxation of the changed neighbourhood, under the same guard and deviation bound; "
         "where that leaves triangles below the target, a last pass allows 1.25 times the bound), "
         "the other parameters as above. Both change the connectivity and the repair also the vertex set, so "
         "they are compared with MeshLab's flipping and remeshing (section \"Local repair against "
         "remeshing\"), not with the smoothers.\n";
  }
  bool pluginRan = false;
  for (const MeshReport& r : reports) {
    const Row* p = r.row("plugin_basic");
    pluginRan = pluginRan || (p && p->m.ok);
  }
  o << "* **MeshLab.** " << meshlabLine << ".";
  if (pluginRan)
    o << " S-ODT basic also runs as the plugin (`filter_sodt`, the shipped `sodt_smoothing.mlx` with `iterations` = "
      << N << ") in the same server: it works on MeshLab's float `CMeshO`.";
  o << "\n";
  o << "* **Time.** In-process rows: wall time of `SodtSmoother::Apply` alone (topology, classification and "
       "sweeps; no I/O), on one thread (`threads` = 1) for every in-process run, so the times are single-core "
       "as in the paper";
  const std::string cpu = processorName();
  if (!cpu.empty())
    o << " (processor: " << cpu << ", " << std::thread::hardware_concurrency() << " hardware threads)";
  o << ". Rows marked † : wall time of the whole meshlabserver run — process start, loading all "
       "plugins, reading and writing the PLY, the filter. Each mesh also lists a no-op run (load and save, no "
       "filter) to subtract. In-process runs shorter than 1 s are repeated (up to " << opt.timingRuns
    << " runs, or until 2 s are spent) and the median is shown; MeshLab runs are single runs. The unguarded "
       "timings of the ODT section follow the same policy. On this shared 2-core machine times under a "
       "few seconds vary by up to about ±30 % between runs (the ODT / S-ODT ratio of blobs_mc was 1.1×, 1.6× and 1.6× "
       "in three runs), so read the ratios below as ranges.\n";
  o << "* **Measures.** Angles: every corner of every triangle, degrees (`computeAngleStats`). `< 30°`: share of "
       "corner angles below 30°. `p1 tri-min`: 1st percentile of the per-triangle smallest angle. Hausdorff: "
       "symmetric, by vcglib sampling (all vertices + max(10000, 2F) random points each way, fixed seed), relative "
       "to the bounding-box diagonal of the input (of the reference for the reference column; `surfaceDistance`). "
       "Volume change: enclosed volume relative to the input's, both closed. Inverted faces: faces whose normal "
       "turned by more than 90° against the same face of the input (only when the connectivity is unchanged).\n\n";

  // MeshLab parameters
  o << "MeshLab 2020.09 filter parameters written into the `.mlx` scripts (all parameters of each filter, exact "
       "names and defaults from the filters' `initParameterSet` in the MeshLab 2020.09 source; `meshlabserver -d` "
       "lists the filter names, which every run checks, and only the parameters' labels, so the comparison tests "
       "check the scripts against the installed plugins' parameter lists with MeshLab's own script parser):\n\n";
  o << "| filter | parameters (name = value) |\n|---|---|\n";
  for (const Method& m : allMethods()) {
    if (m.kind != Kind::Builtin) continue;
    const std::vector<MlxParam> ps = builtinParams(m, N, 1.0, 1.0);
    std::string s;
    for (const MlxParam& q : ps) {
      std::string v = q.value;
      if (q.type == "RichAbsPerc") v = q.note.empty() ? "1% of diagonal" : "input mean edge length";
      if (q.type == "RichEnum") v = q.value + " (" + q.enumValues[std::size_t(std::stoi(q.value))] + ")";
      s += (s.empty() ? "" : ", ") + std::string("`") + q.name + "` = " + v;
      if (q.note.find("matched") != std::string::npos) s += " (matched; " + q.note.substr(q.note.find("default")) ;
    }
    if (ps.empty()) s = "none (one HC pass; the filter has no step count)";
    o << "| " << m.filter << (m.id == "ml_isotropic_edge" ? " (second row)" : m.id == "ml_isotropic_edge_dist" ? " (third row)" : "") << " | " << s << " |\n";
  }
  o << "\nPlanar flipping's `iterations` counts planar-Laplacian relaxation passes after the flips, not steps of "
       "the optimisation (which flips until no flip helps), so its default is kept. The default target length of "
       "the isotropic remeshing (1 % of the diagonal) refines or coarsens the mesh a lot, so a second row keeps "
       "the input's resolution (target = the input's mean edge length). Both remeshing rows and the flipping "
       "change the connectivity: they are not held against the vertex-moving S-ODT rows but against S-ODT "
       "with flips and local repair (section \"Local repair against remeshing\").\n\n";

  // --- Summary
  o << "## Summary\n\n";
  o << "Headline S-ODT variant per mesh (in bold in the per-mesh tables) against the vertex-moving MeshLab "
       "smoothers (Laplacian, HC, Taubin, TwoStep, surface-preserving Laplacian; flipping and remeshing change the "
       "connectivity and are listed separately). \"Beats\" means a larger minimum angle; only smoothers whose "
       "Hausdorff distance to the input is no larger than S-ODT's are held against it — one that moves the "
       "surface further is listed under \"moves further\".\n\n";
  o << "| mesh | V | input min ° | S-ODT variant: min ° / Hausdorff % | numerical ODT min ° | beats (Hausdorff no "
       "larger) | does not beat | moves further | best MeshLab min ° (method, Hausdorff %) | S-ODT inverted / "
       "TwoStep inverted |\n";
  o << "|---|--:|--:|---|--:|---|---|---|---|---|\n";
  for (const MeshReport& r : reports) {
    const Claim c = claimOf(r);
    const Row* odt = r.row("odt");
    const Row* two = r.row("ml_twostep");
    const Row* best = nullptr;
    for (const Row& row : r.rows)
      if (row.method.kind == Kind::Builtin && row.m.ok && (!best || row.m.minDeg > best->m.minDeg)) best = &row;
    o << "| " << r.job.name << " | " << r.input.vertices << " | " << f2(r.input.minDeg) << " | ";
    if (c.sodt && c.sodt->m.ok)
      o << sodt::toString(r.job.variant) << ": " << f2(c.sodt->m.minDeg) << " / " << pct3(c.sodt->m.hausInput);
    else
      o << "n/a";
    o << " | " << (odt && odt->m.ok ? f2(odt->m.minDeg) : "n/a") << " | " << methodsLine(c.beaten) << " | "
      << methodsLine(c.notBeaten) << " | " << methodsLine(c.largerH) << " | ";
    if (best)
      o << f2(best->m.minDeg) << " (" << shortLabel(best->method) << ", " << pct3(best->m.hausInput) << ")";
    else
      o << "n/a";
    o << " | " << (c.sodt && c.sodt->m.ok ? invertedText(c.sodt->m.inverted) : "n/a") << " / "
      << (two && two->m.ok ? invertedText(two->m.inverted) : "n/a") << " |\n";
  }
  {
    int meshes = 0, allBeaten = 0, sodtInv = 0, twoInvMeshes = 0;
    std::vector<std::string> exceptions, twoInv;
    for (const MeshReport& r : reports) {
      const Claim c = claimOf(r);
      if (!c.sodt || !c.sodt->m.ok) continue;
      ++meshes;
      if (c.notBeaten.empty())
        ++allBeaten;
      else
        exceptions.push_back(r.job.name + " (" + methodsLine(c.notBeaten) + ")");
      if (c.sodt->m.inverted > 0) ++sodtInv;
      const Row* two = r.row("ml_twostep");
      if (two && two->m.ok && two->m.inverted > 0) {
        ++twoInvMeshes;
        twoInv.push_back(r.job.name + ": " + std::to_string(two->m.inverted));
      }
    }
    o << "\n**Measured:** on " << allBeaten << " of " << meshes
      << " meshes the headline S-ODT variant has a larger minimum angle than every vertex-moving MeshLab smoother "
         "that stays as close to the input"
      << (exceptions.empty() ? "" : "; not on " + methodsLine(exceptions)) << ". TwoStep Smooth inverted faces on "
      << twoInvMeshes << " of " << meshes << " meshes (faces per mesh: " << methodsLine(twoInv) << "), S-ODT on "
      << sodtInv << ".\n";
  }
  o << "\n";

  repairSection(o, reports);

  // --- ODT
  o << "## S-ODT against the numerical ODT (paper Figure 6)\n\n";
  o << "Same sweeps, same input; only the per-vertex target differs (closed form of the suboptimal Eq. 5 against "
       "Newton on Eq. 3). Two timings, both on one thread:\n\n";
  o << "* **Guarded** (the library defaults, as in every other table): `Apply` with " << N
    << " sweeps, set-up included. The guard (star angles before and after every step, halvings), the Laplacian "
       "fallback and the deviation bound cost the same for both methods, so they shrink the ratio. The quality "
       "columns are from these runs.\n";
  o << "* **Unguarded** (the paper's algorithm: `guard` = none, so no Laplacian fallback and no deviation bound): "
       "S-ODT basic and ODT, " << N
    << " sweeps, timed as the paper compares the solvers: both scalar, one vertex at a time (`simd` off; the "
       "library's default 4-lane AVX2 kernel exists for S-ODT only and makes an unguarded S-ODT sweep about 3x "
       "faster, see bench/README.md). Per sweep: (median time of `Apply` with " << N
    << " sweeps − median time of `Apply` with 0 sweeps, i.e. the set-up: ring topology, vertex order, "
       "colouring) / "
    << N
    << ". Their quality is not reported: without a guard the sweeps can fold faces on meshes with slivers, and "
       "the angles of a folded mesh say nothing about the smoother (last column: faces turned by more than 90° "
       "against the input after the unguarded runs). All other columns are from the guarded runs.\n\n";
  o << "| mesh | V | guarded S-ODT time (s) | guarded ODT time (s) | guarded ODT / S-ODT | unguarded S-ODT ms/sweep | "
       "unguarded ODT ms/sweep | unguarded ODT / S-ODT per sweep | S-ODT min ° | ODT min ° | ODT − S-ODT min ° | "
       "S-ODT p1 ° | ODT p1 ° | S-ODT < 30° | ODT < 30° | unguarded inverted faces S-ODT / ODT |\n";
  o << "|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n";
  auto ms = [](double v) {
    if (v != v) return std::string("n/a");
    char b[32];
    std::snprintf(b, sizeof b, v < 10 ? "%.2f" : (v < 100 ? "%.1f" : "%.0f"), v);
    return std::string(b);
  };
  std::vector<double> ratios, diffs, uratios, guardCost;
  int uMeshes = 0, uSodtFolded = 0, uOdtFolded = 0;
  for (const MeshReport& r : reports) {
    const Row* s = r.row("sodt_basic");
    const Row* d = r.row("odt");
    if (!s || !d || !s->m.ok || !d->m.ok) continue;
    const double ratio = d->m.seconds / s->m.seconds;
    const double diff = d->m.minDeg - s->m.minDeg;
    ratios.push_back(ratio);
    diffs.push_back(diff);
    const UnguardedTiming& u = r.unguarded;
    double uratio = kNaN;
    if (u.ok) {
      uratio = u.odtMsPerSweep() / u.sodtMsPerSweep();
      uratios.push_back(uratio);
      guardCost.push_back(s->m.seconds / u.sodtSeconds);
      ++uMeshes;
      if (u.sodtInverted > 0) ++uSodtFolded;
      if (u.odtInverted > 0) ++uOdtFolded;
    }
    o << "| " << r.job.name << " | " << r.input.vertices << " | " << seconds(s->m.seconds) << " | "
      << seconds(d->m.seconds) << " | " << f2(ratio) << "× | " << (u.ok ? ms(u.sodtMsPerSweep()) : "n/a") << " | "
      << (u.ok ? ms(u.odtMsPerSweep()) : "n/a") << " | " << (u.ok ? f1(uratio) + "×" : "n/a") << " | "
      << f2(s->m.minDeg) << " | " << f2(d->m.minDeg) << " | " << (diff >= 0 ? "+" : "") << f2(diff) << " | "
      << f2(s->m.p1TriMinDeg) << " | " << f2(d->m.p1TriMinDeg) << " | " << f1(100 * s->m.fracBelow30) << "% | "
      << f1(100 * d->m.fracBelow30) << "% | "
      << (u.ok ? invertedText(u.sodtInverted) + " / " + invertedText(u.odtInverted)
               : (u.error.empty() ? std::string("not run") : "failed: " + u.error))
      << " |\n";
  }
  if (!ratios.empty()) {
    std::vector<double> rs = ratios, ds = diffs, us = uratios;
    std::sort(rs.begin(), rs.end());
    std::sort(ds.begin(), ds.end());
    std::sort(us.begin(), us.end());
    // Median: the middle value, or the mean of the two middle values.
    auto median = [](const std::vector<double>& v) {
      const std::size_t n = v.size();
      return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
    };
    const double medR = median(rs), medD = median(ds);
    // The paper (Figure 6 caption): 36 s for 20 S-ODT iterations, 1 min 56 s
    // for 5 L-BFGS iterations on Eq. 3.
    const double paperSodt = 36, paperOdt = 116;
    const double paperPerIt = (paperOdt / 5) / (paperSodt / 20), paperTotal = paperOdt / paperSodt;
    o << "\n**Measured:** ";
    if (!us.empty()) {
      const double medU = median(us);
      o << "without guard (the paper's algorithm, set-up excluded) an ODT sweep took " << f1(us.front()) << "× to "
        << f1(us.back()) << "× the time of an S-ODT sweep (median " << f1(medU) << "× over " << us.size()
        << " meshes). With the guards (the library defaults, set-up included) the numerical ODT took " << f2(rs.front())
        << "× to " << f2(rs.back()) << "× the time of S-ODT (median " << f2(medR) << "× over " << rs.size()
        << " meshes). ";
      std::vector<double> gc = guardCost;
      std::sort(gc.begin(), gc.end());
      o << "A guarded S-ODT run took " << f1(gc.front()) << "× to " << f1(gc.back())
        << "× the time of an unguarded one (both " << N << " sweeps, set-up included)";
      if (gc.front() >= 2)
        o << ": the guard's work, the same for both methods, is most of a guarded S-ODT sweep and hides the gap "
             "between the two local solvers. ";
      else
        o << ". ";
      o << "The paper (Section 3, Figure 6; 129K-vertex RyR model) reports 36 s for 20 S-ODT iterations against 1 "
           "min 56 s for 5 L-BFGS iterations on Eq. 3: "
        << f1(paperTotal) << "× in total and " << f1(paperPerIt) << "× per iteration. ";
      o << "The unguarded per-sweep median, " << f1(medU) << "×, is " << f2(medU / paperPerIt)
        << " times the paper's per-iteration ratio; at the paper's iteration counts (5 ODT sweeps against 20 S-ODT sweeps) it would give " << f1(medU / 4)
        << "× in total (median; arithmetic on the per-sweep times, not a measured run) against the paper's "
        << f1(paperTotal) << "×. The two ODTs are not the same solver, though: ours is a per-vertex Newton solve in "
           "2 variables (at most 50 iterations; measured on the input stars of blobs_mc, sphere_jitter, mol_a and "
           "bunny_closed: 2.6 to 3.0 on average) inside the Gauss-Seidel sweep, the paper's a global L-BFGS "
           "solve, so only the orders of magnitude compare. ";
    } else {
      o << "the numerical ODT took " << f2(rs.front()) << "× to " << f2(rs.back()) << "× the time of S-ODT (median "
        << f2(medR) << "×) over " << rs.size() << " meshes, with the guards (no unguarded timings in this run). ";
    }
    const double maxAbsD = std::max(std::abs(ds.front()), std::abs(ds.back()));
    o << "Quality (guarded runs): ODT's minimum angle differed from S-ODT's by " << (ds.front() >= 0 ? "+" : "")
      << f2(ds.front()) << "° to " << (ds.back() >= 0 ? "+" : "") << f2(ds.back()) << "° (median "
      << (medD >= 0 ? "+" : "") << f2(medD) << "°; positive: ODT better); ";
    if (maxAbsD <= 2.0)
      o << "the paper's \"little difference\" in quality is confirmed (minimum angles within " << f2(maxAbsD)
        << "°).";
    else
      o << "the minimum angles differ by up to " << f2(maxAbsD) << "°, more than the paper's \"little difference\".";
    if (uMeshes > 0)
      o << " Unguarded, S-ODT inverted faces on " << uSodtFolded << " of " << uMeshes << " meshes and ODT on "
        << uOdtFolded << " of " << uMeshes
        << " (last column); the unguarded runs are used for timing only, and their angles are not compared.";
    o << "\n\n";
  }
  o << "![S-ODT vs numerical ODT: time and minimum angle](" << figDir << "/" << odtSummaryFile() << ")\n\n";

  // --- Paper tables
  bool anyPaper = false;
  for (const MeshReport& r : reports) anyPaper = anyPaper || findPaperRow(r.job.paperModel);
  if (anyPaper) {
    o << "## The paper's Tables 3-4 side by side\n\n";
    o << "Paper values quoted from " << kCitation
      << ", Table 3 (\"Comparisons of min-angle improvement\", 20 iterations) and Table 4 (\"Comparisons of "
         "running time (in seconds)\", Pentium IV 2.0 GHz). Ohtake's is the paper's comparison method; it is not "
         "in MeshLab, so its column stands next to MeshLab's best vertex-moving smoother here.\n\n";
    o << "| model | paper V | paper: original min | paper: S-ODT min (alg.) | paper: Ohtake's min | paper: S-ODT time "
         "(s) | paper: Ohtake's time (s) | here: mesh (V) | here: input min | here: S-ODT min (alg.) | here: S-ODT "
         "time (s) | here: best MeshLab smoother min (method) |\n";
    o << "|---|--:|--:|--:|--:|--:|--:|---|--:|--:|--:|---|\n";
    for (const MeshReport& r : reports) {
      const PaperRow* p = findPaperRow(r.job.paperModel);
      if (!p) continue;
      const Row* s = r.row(variantId(r.job.variant));
      const Row* best = nullptr;
      for (const Row& row : r.rows)
        if (isSmootherRow(row) && (!best || row.m.minDeg > best->m.minDeg)) best = &row;
      o << "| " << p->model << " | " << p->vertices << " | " << f1(p->originalMin) << "° | " << f1(p->oursMin)
        << "° (" << p->alg << ") | " << f1(p->ohtakeMin) << "° | " << f1(p->oursSeconds) << " | "
        << f1(p->ohtakeSeconds) << " | " << r.job.name << " (" << r.input.vertices << ") | " << f2(r.input.minDeg)
        << "° | " << (s && s->m.ok ? f2(s->m.minDeg) : "n/a") << "° (" << sodt::toString(r.job.variant) << ") | "
        << (s && s->m.ok ? seconds(s->m.seconds) : "n/a") << " | "
        << (best ? f2(best->m.minDeg) + "° (" + shortLabel(best->method) + ")" : "n/a") << " |\n";
    }
    o << "\n";
    for (const MeshReport& r : reports) {
      const PaperRow* p = findPaperRow(r.job.paperModel);
      if (!p) continue;
      if (std::abs(r.input.minDeg - p->originalMin) > 0.5)
        o << "* **" << r.job.name << "**: the input is not the paper's mesh as measured — its smallest angle is "
          << f2(r.input.minDeg) << "° here against " << f1(p->originalMin) << "° in the paper"
          << (r.input.vertices == p->vertices ? " (same vertex count, " + std::to_string(p->vertices) + ")" : "")
          << ": compare the gains, not the absolute angles.\n";
      const Row* s = r.row(variantId(r.job.variant));
      if (s && s->m.ok)
        o << "* **" << r.job.name << "**: S-ODT " << sodt::toString(r.job.variant) << " took " << seconds(s->m.seconds)
          << " s here (" << N << " sweeps, one core of this machine) against " << f1(p->oursSeconds)
          << " s in the paper (20 iterations, 2.0 GHz Pentium IV).\n";
    }
    o << "\n";
  }

  // --- Per mesh
  o << "## Per mesh\n\n";
  o << "Bold: the headline S-ODT variant of the mesh. † time of the whole meshlabserver run (see Setup). "
       "\"other connectivity\": edge flips, the local repair or remeshing changed the faces, so faces cannot be "
       "compared one by one; V and F then show what changed (the notes under the table list the vertices the "
       "repair added and removed).\n\n";
  for (const MeshReport& r : reports) {
    o << "### " << r.job.name << "\n\n";
    o << "`" << r.job.path << "`: " << r.input.vertices << " vertices, " << r.input.faces << " faces, "
      << (r.input.closed ? "closed" : "open") << ". Headline variant: " << sodt::toString(r.job.variant) << ".";
    if (!r.job.reference.empty()) o << " Reference (clean) mesh: `" << r.job.reference << "`.";
    if (!r.job.paperModel.empty()) o << " Stands for the paper's \"" << r.job.paperModel << "\".";
    if (r.noopSeconds == r.noopSeconds)
      o << " meshlabserver no-op run (load + save): " << seconds(r.noopSeconds) << " s.";
    o << "\n\n";
    perMeshTable(o, r);
    o << "\n";
    for (const Row& row : r.rows)
      if (row.m.ok && row.method.kind == Kind::InProcess && !row.m.detail.empty())
        o << "* " << row.method.label << ": " << row.m.detail << ".\n";
    for (const std::string& n : r.notes) o << "* " << n << "\n";
    o << "\n![Angle histograms, " << r.job.name << "](" << figDir << "/" << histogramFile(r) << ")\n\n";
    if (!r.sodtCurve.minDeg.empty()) {
      o << "![Min/max angle per sweep, " << r.job.name << "](" << figDir << "/" << convergenceFile(r) << ")\n\n";
      const Row* s = r.row("sodt_basic");
      const Row* d = r.row("odt");
      o << "Per-sweep curves (paper Figure 4). Solid: the state after sweep k of the " << N
        << "-sweep run in the table, measured by a k-sweep run from the input for each k (end points: S-ODT "
        << f2(r.sodtCurve.minDeg.back()) << "°, ODT " << f2(r.odtCurve.minDeg.back()) << "°; table: "
        << (s && s->m.ok ? f2(s->m.minDeg) : "n/a") << "°, " << (d && d->m.ok ? f2(d->m.minDeg) : "n/a")
        << "°). Dashed: one sweep per call, each call on the previous result (S-ODT "
        << f2(r.sodtSteps.minDeg.back()) << "°, ODT " << f2(r.odtSteps.minDeg.back())
        << "° after " << N << " calls; " << seconds(r.sodtSteps.seconds.back()) << " s and "
        << seconds(r.odtSteps.seconds.back())
        << " s in total).";
      const bool differ = std::abs(r.sodtSteps.minDeg.back() - r.sodtCurve.minDeg.back()) > 0.01 ||
                          std::abs(r.odtSteps.minDeg.back() - r.odtCurve.minDeg.back()) > 0.01;
      if (differ)
        o << " The two differ because every call takes its input as the surface the 0.1 % deviation bound refers "
             "to, so one-sweep calls let vertices drift by up to 0.1 % of the diagonal per call.";
      o << "\n\n";
    }
  }
  return o.str();
}

// ---------------------------------------------------------------------------
// Figures

std::string histogramSvg(const MeshReport& r) {
  std::vector<const Row*> rows;
  for (const Row& row : r.rows)
    if (row.m.ok && !row.m.histogram.empty()) rows.push_back(&row);
  const int cols = 3, pw = 320, ph = 170;
  const int nrows = std::max<int>(1, int((rows.size() + cols - 1) / cols));
  const int W = cols * pw + 10, H = 50 + nrows * ph;
  svg::Doc d(W, H, "Angle histograms of " + r.job.name);
  d.text(10, 18, "Corner-angle histograms, " + r.job.name + " (1° bins, % of all angles)", 13, "start", "#222", 0,
         true);
  d.legend(10, 38, {{"#c8c8c8", "input"}, {"#1f77b4", "after the method (colour per method)"},
                    {"#d62728", "min / max angle after"}},
           true, 0);
  auto toPct = [](const std::vector<long long>& h) {
    long long total = 0;
    for (long long c : h) total += c;
    std::vector<double> v(h.size(), 0);
    for (std::size_t i = 0; i < h.size(); ++i) v[i] = total ? 100.0 * double(h[i]) / double(total) : 0;
    return v;
  };
  const std::vector<double> in = toPct(r.input.histogram);
  const double inMax = *std::max_element(in.begin(), in.end());
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const Row& row = *rows[k];
    const int cx = int(k % cols) * pw, cy = 50 + int(k / cols) * ph;
    const std::vector<double> out = toPct(row.m.histogram);
    const double yMax = svg::niceCeil(std::max(inMax, *std::max_element(out.begin(), out.end())));
    svg::Axes a;
    a.x = cx + 48;
    a.y = cy + 22;
    a.w = pw - 62;
    a.h = ph - 62;
    a.x0 = 0;
    a.x1 = 180;
    a.y0 = 0;
    a.y1 = yMax;
    d.text(cx + 48, cy + 14, row.method.label, 11, "start", "#222", 0, true);
    d.stepHistogram(a, in, "#c8c8c8", "none");
    d.stepHistogram(a, out, "none", row.method.colour, 1.3);
    for (double v : {row.m.minDeg, row.m.maxDeg}) d.line(a.px(v), a.y, a.px(v), a.y + a.h, "#d62728", 1, "3,2");
    d.text(a.x + a.w - 2, a.y + 11, "min " + svg::num(row.m.minDeg, 1) + "°  max " + svg::num(row.m.maxDeg, 1) + "°",
           10, "end", "#d62728");
    d.axes(a, {0, 30, 60, 90, 120, 150, 180}, {0, yMax / 2, yMax}, "angle (degrees)", "%", 2);
  }
  return d.str();
}

std::string convergenceSvg(const MeshReport& r) {
  const int W = 760, H = 310;
  svg::Doc d(W, H, "Min and max angle per sweep, " + r.job.name);
  d.text(10, 18, "Minimum and maximum angle per sweep, " + r.job.name, 13, "start", "#222", 0, true);
  const Method* sm = findMethod("sodt_basic");
  const Method* om = findMethod("odt");
  struct Series {
    const Curve* c;
    std::string colour, dash, label;
  };
  const std::vector<Series> series = {
      {&r.sodtCurve, sm->colour, "", "S-ODT basic (Alg. 1)"},
      {&r.odtCurve, om->colour, "", "numerical ODT (Eq. 3)"},
      {&r.sodtSteps, sm->colour, "5,3", "S-ODT, one sweep per call"},
      {&r.odtSteps, om->colour, "5,3", "ODT, one sweep per call"},
  };
  for (std::size_t i = 0; i < series.size(); ++i) {
    const double x = 10 + 185 * double(i);
    d.line(x, 34, x + 22, 34, series[i].colour, 2, series[i].dash);
    d.text(x + 27, 38, series[i].label, 11);
  }
  const int n = int(r.sodtCurve.minDeg.size());
  for (int panel = 0; panel < 2; ++panel) {
    const bool isMin = panel == 0;
    std::vector<double> all;
    for (const Series& s : series)
      for (double v : isMin ? s.c->minDeg : s.c->maxDeg) all.push_back(v);
    if (all.empty()) continue;
    double lo = *std::min_element(all.begin(), all.end()), hi = *std::max_element(all.begin(), all.end());
    const double pad = std::max(0.5, 0.08 * (hi - lo));
    lo = std::max(0.0, lo - pad);
    hi = std::min(180.0, hi + pad);
    const std::vector<double> yt = svg::niceTicks(lo, hi, 5);
    svg::Axes a;
    a.x = 60 + panel * 370;
    a.y = 62;
    a.w = 300;
    a.h = 190;
    a.x0 = 0;
    a.x1 = std::max(1, n - 1);
    a.y0 = std::min(lo, yt.front());
    a.y1 = std::max(hi, yt.back());
    d.text(a.x, a.y - 5, isMin ? "(a) minimum angle" : "(b) maximum angle", 11, "start", "#222", 0, true);
    d.axes(a, svg::niceTicks(0, n - 1, 5), yt, "sweeps", isMin ? "min angle (°)" : "max angle (°)", 1);
    for (const Series& s : series) {
      std::vector<std::pair<double, double>> pts;
      const std::vector<double>& v = isMin ? s.c->minDeg : s.c->maxDeg;
      for (std::size_t i = 0; i < v.size(); ++i) pts.push_back({double(i), v[i]});
      d.polyline(a, pts, s.colour, s.dash.empty() ? 1.8 : 1.3, s.dash.empty(), s.dash);
    }
  }
  d.text(10, H - 8,
         "Solid: state after sweep k of the table's run (a k-sweep run from the input per k). Dashed: one sweep "
         "per call, each on the previous result.",
         10);
  return d.str();
}

std::string odtSummarySvg(const std::vector<MeshReport>& reports, int iterations) {
  struct Item {
    std::string name;
    double ts, to, in, ms, mo;
    double us, uo;  ///< unguarded ms per sweep (NaN: not run)
  };
  std::vector<Item> items;
  for (const MeshReport& r : reports) {
    const Row* s = r.row("sodt_basic");
    const Row* o = r.row("odt");
    if (!s || !o || !s->m.ok || !o->m.ok) continue;
    const UnguardedTiming& u = r.unguarded;
    items.push_back({r.job.name, s->m.seconds, o->m.seconds, r.input.minDeg, s->m.minDeg, o->m.minDeg,
                     u.ok ? u.sodtMsPerSweep() : kNaN, u.ok ? u.odtMsPerSweep() : kNaN});
  }
  bool anyU = false;
  for (const Item& it : items) anyU = anyU || (it.us == it.us && it.uo == it.uo);
  // Horizontal bars: one group per mesh (names on the left); panels (a) guarded
  // time, (b) unguarded time per sweep when measured, then the minimum angle.
  const int npanels = anyU ? 3 : 2;
  const int n = std::max<int>(1, int(items.size()));
  const double group = 40;
  const int top = 66, nameW = 130, pw = anyU ? 250 : 300, gap = 90;
  const int W = nameW + npanels * pw + (npanels - 1) * gap + 40, H = top + int(group * n) + 60;
  svg::Doc d(W, H, "S-ODT vs numerical ODT");
  d.text(10, 18,
         "S-ODT (Alg. 1) vs numerical ODT (Eq. 3): " + std::to_string(iterations) + " sweeps, one thread" +
             (anyU ? "; guarded (library defaults) and unguarded (guard none, the paper's algorithm)" : ", same guard"),
         13, "start", "#222", 0, true);
  const std::string cs = findMethod("sodt_basic")->colour, co = findMethod("odt")->colour;
  d.legend(10, 38, {{"#c8c8c8", "input"}, {cs, "S-ODT basic"}, {co, "numerical ODT"}}, true, 150);
  auto logRange = [](double lo, double hi, double& l0, double& l1) {
    if (!(lo > 0) || !(hi >= lo)) lo = 0.01, hi = 1;
    l0 = std::pow(10.0, std::floor(std::log10(lo)));
    l1 = std::pow(10.0, std::ceil(std::log10(hi)));
    if (l1 <= l0) l1 = l0 * 10;
  };
  double tMin = 1e300, tMax = 0, uMin = 1e300, uMax = 0, mMax = 0;
  for (const Item& it : items) {
    tMin = std::min({tMin, it.ts, it.to});
    tMax = std::max({tMax, it.ts, it.to});
    if (it.us == it.us && it.uo == it.uo && it.us > 0 && it.uo > 0) {
      uMin = std::min({uMin, it.us, it.uo});
      uMax = std::max({uMax, it.us, it.uo});
    }
    mMax = std::max({mMax, it.in, it.ms, it.mo});
  }
  if (items.empty()) mMax = 60;
  double t0, t1, u0, u1;
  logRange(tMin, tMax, t0, t1);
  logRange(uMin, uMax, u0, u1);
  for (int panel = 0; panel < npanels; ++panel) {
    // 0: guarded time (s, log); 1: unguarded ms per sweep (log) when measured; last: min angle.
    const int kind = panel == npanels - 1 ? 2 : panel;
    const double x0 = nameW + panel * (pw + gap), y0 = top;
    const bool logX = kind != 2;
    const double v0 = kind == 0 ? t0 : (kind == 1 ? u0 : 0);
    const double v1 = kind == 0 ? t1 : (kind == 1 ? u1 : svg::niceCeil(mMax * 1.05));
    auto X = [&](double v) {
      if (logX)
        return x0 + (std::log10(std::max(v, v0)) - std::log10(v0)) / (std::log10(v1) - std::log10(v0)) * pw;
      return x0 + (v - v0) / (v1 - v0) * pw;
    };
    const double h = group * n;
    const char* title = kind == 0 ? "(a) guarded: wall time of Apply (s, log)"
                                  : (kind == 1 ? "(b) unguarded: ms per sweep (log)"
                                               : (anyU ? "(c) minimum angle, guarded (°)" : "(b) minimum angle (°)"));
    d.text(x0, y0 - 8, title, 11, "start", "#222", 0, true);
    std::vector<double> ticks;
    if (logX)
      for (double v = v0; v <= v1 * 1.0001; v *= 10) ticks.push_back(v);
    else
      ticks = svg::niceTicks(0, v1, 5);
    for (double t : ticks) {
      d.line(X(t), y0, X(t), y0 + h, "#e4e4e4");
      d.line(X(t), y0 + h, X(t), y0 + h + 4, "#444");
      d.text(X(t), y0 + h + 15, svg::num(t, 3), 10, "middle");
    }
    d.rect(x0, y0, pw, h, "none", "#444");
    d.text(x0 + pw / 2, y0 + h + 30, kind == 0 ? "seconds" : (kind == 1 ? "milliseconds per sweep" : "degrees"), 11,
           "middle");
    for (std::size_t i = 0; i < items.size(); ++i) {
      const Item& it = items[i];
      const double gy = y0 + group * double(i);
      if (panel == 0) d.text(x0 - 8, gy + group / 2 + 4, it.name, 11, "end");
      std::vector<std::pair<double, std::string>> bars;
      if (kind == 0)
        bars = {{it.ts, cs}, {it.to, co}};
      else if (kind == 1)
        bars = {{it.us, cs}, {it.uo, co}};
      else
        bars = {{it.in, "#c8c8c8"}, {it.ms, cs}, {it.mo, co}};
      if (kind == 1 && !(it.us == it.us && it.uo == it.uo)) {
        d.text(x0 + 5, gy + group / 2 + 4, "not measured", 10);
        continue;
      }
      const double bh = (group - 10) / double(bars.size());
      double right = x0;
      for (std::size_t b = 0; b < bars.size(); ++b) {
        const double xe = X(bars[b].first);
        d.rect(x0, gy + 5 + bh * double(b), std::max(0.5, xe - x0), bh - 1, bars[b].second);
        right = std::max(right, xe);
      }
      const std::string label = kind == 0   ? svg::num(it.to / it.ts, 2) + "×"
                                : kind == 1 ? svg::num(it.uo / it.us, 1) + "×"
                                            : (it.mo - it.ms >= 0 ? "+" : "") + svg::num(it.mo - it.ms, 2) + "°";
      d.text(right + 5, gy + group / 2 + 4, label, 10);
    }
  }
  d.text(10, H - 8,
         anyU ? "Labels: (a), (b) ODT time / S-ODT time; (c) ODT min angle − S-ODT min angle. (b) excludes the "
                "set-up (a 0-sweep run); unguarded quality is not shown (folds)."
              : "Labels: (a) ODT time / S-ODT time; (b) ODT min angle − S-ODT min angle.",
         10);
  return d.str();
}

}  // namespace sodtcmp
