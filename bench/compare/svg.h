// SPDX-License-Identifier: GPL-3.0-or-later
// A few SVG primitives for the comparison figures: a document with a title,
// panels with linear axes, lines, step histograms, bars and legends.
#pragma once

#include <string>
#include <utility>
#include <vector>

namespace sodtcmp {
namespace svg {

/// A plot area at (x, y) of size w x h (pixels) showing [x0, x1] x [y0, y1];
/// logY maps y through log10 (y0, y1 > 0).
struct Axes {
  double x = 0, y = 0, w = 100, h = 100;
  double x0 = 0, x1 = 1, y0 = 0, y1 = 1;
  bool logY = false;
  double px(double v) const;
  double py(double v) const;
};

class Doc {
 public:
  Doc(int width, int height, const std::string& title);
  /// Text; anchor "start" | "middle" | "end"; optional rotation in degrees.
  void text(double x, double y, const std::string& s, int size = 11, const std::string& anchor = "start",
            const std::string& colour = "#222", double rotate = 0, bool bold = false);
  void line(double x1, double y1, double x2, double y2, const std::string& colour, double width = 1,
            const std::string& dash = "");
  void rect(double x, double y, double w, double h, const std::string& fill, const std::string& stroke = "none");
  void circle(double x, double y, double r, const std::string& fill, const std::string& stroke = "none");
  /// Frame, ticks and tick labels; labels on the x and y axes.
  void axes(const Axes& a, const std::vector<double>& xticks, const std::vector<double>& yticks,
            const std::string& xlabel, const std::string& ylabel, int tickDigits = 3);
  /// Polyline through data points (NaNs skipped), optional dots.
  void polyline(const Axes& a, const std::vector<std::pair<double, double>>& pts, const std::string& colour,
                double width = 1.5, bool dots = false, const std::string& dash = "");
  /// Step outline of a histogram with unit-width bins starting at 0 (values
  /// in data units), filled or stroked; runs of equal height are merged so
  /// the path stays short.
  void stepHistogram(const Axes& a, const std::vector<double>& bins, const std::string& fill,
                     const std::string& stroke, double strokeWidth = 1.2);
  /// Legend rows (colour swatch + label) starting at (x, y).
  void legend(double x, double y, const std::vector<std::pair<std::string, std::string>>& entries,
              bool horizontal = false, double spacing = 0);
  std::string str() const;

 private:
  int width_, height_;
  std::string body_;
};

/// About n round tick values covering [lo, hi].
std::vector<double> niceTicks(double lo, double hi, int n = 5);
/// A round number >= v (1, 2, 2.5, 5 x 10^k).
double niceCeil(double v);
/// Fixed-point text without trailing zeros.
std::string num(double v, int decimals = 2);

}  // namespace svg
}  // namespace sodtcmp
