// SPDX-License-Identifier: GPL-3.0-or-later
#include "svg.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <sstream>

namespace sodtcmp {
namespace svg {

namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

}  // namespace

std::string num(double v, int decimals) {
  if (!std::isfinite(v)) return "0";
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*f", decimals, v);
  std::string s = buf;
  if (s.find('.') != std::string::npos) {
    while (!s.empty() && s.back() == '0') s.pop_back();
    if (!s.empty() && s.back() == '.') s.pop_back();
  }
  if (s == "-0") s = "0";
  return s;
}

double Axes::px(double v) const { return x + (v - x0) / (x1 - x0) * w; }

double Axes::py(double v) const {
  if (logY) {
    const double l = std::log10(std::max(v, 1e-300));
    return y + h - (l - std::log10(y0)) / (std::log10(y1) - std::log10(y0)) * h;
  }
  return y + h - (v - y0) / (y1 - y0) * h;
}

Doc::Doc(int width, int height, const std::string& title) : width_(width), height_(height) {
  body_ += "<title>" + esc(title) + "</title>\n";
  body_ += "<rect width=\"100%\" height=\"100%\" fill=\"#fff\"/>\n";
}

void Doc::text(double x, double y, const std::string& s, int size, const std::string& anchor,
               const std::string& colour, double rotate, bool bold) {
  body_ += "<text x=\"" + num(x, 1) + "\" y=\"" + num(y, 1) + "\"";
  if (size != 11) body_ += " font-size=\"" + std::to_string(size) + "\"";
  if (anchor != "start") body_ += " text-anchor=\"" + anchor + "\"";
  if (colour != "#222") body_ += " fill=\"" + colour + "\"";
  if (bold) body_ += " font-weight=\"bold\"";
  if (rotate != 0) body_ += " transform=\"rotate(" + num(rotate, 1) + " " + num(x, 1) + " " + num(y, 1) + ")\"";
  body_ += ">" + esc(s) + "</text>\n";
}

void Doc::line(double x1, double y1, double x2, double y2, const std::string& colour, double width,
               const std::string& dash) {
  body_ += "<line x1=\"" + num(x1, 1) + "\" y1=\"" + num(y1, 1) + "\" x2=\"" + num(x2, 1) + "\" y2=\"" +
           num(y2, 1) + "\" stroke=\"" + colour + "\"";
  if (width != 1) body_ += " stroke-width=\"" + num(width, 2) + "\"";
  if (!dash.empty()) body_ += " stroke-dasharray=\"" + dash + "\"";
  body_ += "/>\n";
}

void Doc::rect(double x, double y, double w, double h, const std::string& fill, const std::string& stroke) {
  body_ += "<rect x=\"" + num(x, 1) + "\" y=\"" + num(y, 1) + "\" width=\"" + num(w, 1) + "\" height=\"" +
           num(h, 1) + "\" fill=\"" + fill + "\"";
  if (stroke != "none") body_ += " stroke=\"" + stroke + "\"";
  body_ += "/>\n";
}

void Doc::circle(double x, double y, double r, const std::string& fill, const std::string& stroke) {
  body_ += "<circle cx=\"" + num(x, 1) + "\" cy=\"" + num(y, 1) + "\" r=\"" + num(r, 1) + "\" fill=\"" + fill + "\"";
  if (stroke != "none") body_ += " stroke=\"" + stroke + "\"";
  body_ += "/>\n";
}

void Doc::axes(const Axes& a, const std::vector<double>& xticks, const std::vector<double>& yticks,
               const std::string& xlabel, const std::string& ylabel, int tickDigits) {
  rect(a.x, a.y, a.w, a.h, "none", "#444");
  for (double t : xticks) {
    const double X = a.px(t);
    line(X, a.y + a.h, X, a.y + a.h + 4, "#444");
    text(X, a.y + a.h + 15, num(t, tickDigits), 10, "middle");
  }
  for (double t : yticks) {
    const double Y = a.py(t);
    line(a.x - 4, Y, a.x, Y, "#444");
    line(a.x, Y, a.x + a.w, Y, "#e4e4e4");
    text(a.x - 6, Y + 3.5, num(t, tickDigits), 10, "end");
  }
  if (!xlabel.empty()) text(a.x + a.w / 2, a.y + a.h + 30, xlabel, 11, "middle");
  if (!ylabel.empty()) text(a.x - 38, a.y + a.h / 2, ylabel, 11, "middle", "#222", -90);
}

void Doc::polyline(const Axes& a, const std::vector<std::pair<double, double>>& pts, const std::string& colour,
                   double width, bool dots, const std::string& dash) {
  std::string d;
  for (const auto& p : pts) {
    if (!std::isfinite(p.first) || !std::isfinite(p.second)) continue;
    d += (d.empty() ? "" : " ") + num(a.px(p.first), 1) + "," + num(a.py(p.second), 1);
  }
  if (d.empty()) return;
  body_ += "<polyline points=\"" + d + "\" fill=\"none\" stroke=\"" + colour + "\" stroke-width=\"" + num(width, 2) +
           "\"";
  if (!dash.empty()) body_ += " stroke-dasharray=\"" + dash + "\"";
  body_ += "/>\n";
  if (dots)
    for (const auto& p : pts)
      if (std::isfinite(p.first) && std::isfinite(p.second)) circle(a.px(p.first), a.py(p.second), 2, colour);
}

void Doc::stepHistogram(const Axes& a, const std::vector<double>& bins, const std::string& fill,
                        const std::string& stroke, double strokeWidth) {
  // Pixel coordinates: absolute heights (V), relative bin widths (h); runs of
  // bins within half a pixel of the same height are merged.
  const double bw = (a.px(1) - a.px(0));
  const double base = a.py(0);
  std::string d = "M" + num(a.px(0), 1) + " " + num(base, 1);
  double cur = base;
  int run = 0;  // bins at the current height not yet written
  for (std::size_t b = 0; b < bins.size(); ++b) {
    const double Y = a.py(std::min(bins[b], a.y1));
    if (std::abs(Y - cur) < 0.5) {
      ++run;
      continue;
    }
    if (run > 0) d += "h" + num(bw * run, 2);
    d += "V" + num(Y, 1);
    cur = Y;
    run = 1;
  }
  if (run > 0) d += "h" + num(bw * run, 2);
  d += "V" + num(base, 1);
  if (fill != "none") d += "Z";
  body_ += "<path d=\"" + d + "\" fill=\"" + fill + "\"";
  body_ += " stroke=\"" + stroke + "\"";
  if (stroke != "none") body_ += " stroke-width=\"" + num(strokeWidth, 2) + "\" stroke-linejoin=\"round\"";
  body_ += "/>\n";
}

void Doc::legend(double x, double y, const std::vector<std::pair<std::string, std::string>>& entries,
                 bool horizontal, double spacing) {
  double X = x, Y = y;
  for (const auto& e : entries) {
    rect(X, Y - 9, 14, 10, e.first);
    text(X + 19, Y, e.second, 11);
    if (horizontal)
      X += spacing > 0 ? spacing : 30 + 6.2 * double(e.second.size());
    else
      Y += spacing > 0 ? spacing : 16;
  }
}

std::string Doc::str() const {
  std::ostringstream o;
  o << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << width_ << "\" height=\"" << height_
    << "\" viewBox=\"0 0 " << width_ << " " << height_ << "\" font-family=\"DejaVu Sans, Arial, sans-serif\""
    << " font-size=\"11\">\n"
    << body_ << "</svg>\n";
  return o.str();
}

double niceCeil(double v) {
  if (!(v > 0) || !std::isfinite(v)) return 1;
  const double e = std::pow(10.0, std::floor(std::log10(v)));
  for (double m : {1.0, 2.0, 2.5, 5.0, 10.0})
    if (m * e >= v * (1 - 1e-12)) return m * e;
  return 10 * e;
}

std::vector<double> niceTicks(double lo, double hi, int n) {
  std::vector<double> t;
  if (!(hi > lo)) return {lo};
  const double step = niceCeil((hi - lo) / std::max(1, n));
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + 1e-9 * step; v += step)
    t.push_back(std::abs(v) < 1e-12 * step ? 0.0 : v);
  return t;
}

}  // namespace svg
}  // namespace sodtcmp
