#include "plot_draw.hpp"
#include "util/number_text.hpp"

#include <cairo.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>

namespace fibrodem::cairo {

namespace {

struct Rgb {
  double r, g, b;
};

// Matplotlib's tab10, the usual distinguishable colours.
constexpr Rgb kPalette[] = {{0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.173, 0.627, 0.173},
                            {0.839, 0.153, 0.157}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
                            {0.890, 0.467, 0.761}, {0.498, 0.498, 0.498}, {0.737, 0.741, 0.133},
                            {0.090, 0.745, 0.812}};
constexpr int kPaletteSize = sizeof(kPalette) / sizeof(kPalette[0]);

struct Axis {
  bool log = true;
  double lo = 1, hi = 10;  // data units
  double f(double v) const { return log ? std::log10(v) : v; }
  bool drawable(double v) const { return std::isfinite(v) && (!log || v > 0); }
  double frac(double v) const { return (f(v) - f(lo)) / (f(hi) - f(lo)); }
};

// A log axis spans whole decades; a linear one "nice" round numbers.
Axis make_axis(bool log, std::vector<double> values) {
  Axis a;
  a.log = log;
  values.erase(std::remove_if(values.begin(), values.end(), [&](double v) { return !a.drawable(v); }), values.end());
  if (values.empty()) {
    a.lo = log ? 1 : 0;
    a.hi = 10;
    return a;
  }
  const auto [mn, mx] = std::minmax_element(values.begin(), values.end());
  if (log) {
    // Whole decades, with a little room so that markers on a decade are whole.
    double lo = std::floor(std::log10(*mn) + 1e-9), hi = std::ceil(std::log10(*mx) - 1e-9);
    if (hi <= lo) hi = lo + 1;
    const double pad = 0.04 * (hi - lo);
    a.lo = std::pow(10.0, lo - pad);
    a.hi = std::pow(10.0, hi + pad);
  } else {
    double lo = *mn, hi = *mx;
    if (hi <= lo) {
      lo -= 1;
      hi += 1;
    }
    const double step = std::pow(10.0, std::floor(std::log10((hi - lo) / 5)));
    a.lo = std::floor(lo / step) * step;
    a.hi = std::ceil(hi / step) * step;
    // A little room, so that markers and error bars on the ends are whole.
    if (*mn - a.lo < 0.03 * (a.hi - a.lo)) a.lo -= 0.04 * (a.hi - a.lo);
    if (a.hi - *mx < 0.03 * (a.hi - a.lo)) a.hi += 0.04 * (a.hi - a.lo);
  }
  return a;
}

struct Tick {
  double value;
  bool major;
  int decade;  // log axes: the exponent of a major tick
};

std::vector<Tick> ticks_of(const Axis& a) {
  std::vector<Tick> ticks;
  if (a.log) {
    const int lo = static_cast<int>(std::ceil(std::log10(a.lo) - 1e-9));
    const int hi = static_cast<int>(std::floor(std::log10(a.hi) + 1e-9));
    const int every = std::max(1, (hi - lo + 7) / 8);  // at most ~8 labelled decades
    for (int k = lo - 1; k <= hi; ++k) {
      if (k >= lo) ticks.push_back({std::pow(10.0, k), (k - lo) % every == 0, k});
      if (hi - lo <= 6)
        for (int m = 2; m <= 9; ++m)
          if (const double v = m * std::pow(10.0, k); v > a.lo && v < a.hi) ticks.push_back({v, false, k});
    }
  } else {
    const double step = std::pow(10.0, std::floor(std::log10((a.hi - a.lo) / 5)));
    double s = step;
    while ((a.hi - a.lo) / s > 8) s *= 2;
    for (double v = std::ceil(a.lo / s) * s; v <= a.hi + 1e-9 * s; v += s) ticks.push_back({v, true, 0});
  }
  return ticks;
}

// A tick label: 6 significant digits, a rounding residue near 0 as 0.
std::string number_text(double v) { return significant_digits(std::abs(v) < 1e-12 ? 0.0 : v, 6); }

double text_width(cairo_t* c, const std::string& s) {
  cairo_text_extents_t e;
  cairo_text_extents(c, s.c_str(), &e);
  return e.x_advance;
}

// "10" with the exponent raised; returns the width. align: 0 left, 0.5 centre, 1 right of x.
double draw_power(cairo_t* c, double x, double y, int exponent, double font, double align) {
  const std::string base = "10", exp = std::to_string(exponent);
  cairo_set_font_size(c, font);
  const double wb = text_width(c, base);
  cairo_set_font_size(c, 0.72 * font);
  const double we = text_width(c, exp);
  const double w = wb + we + 1;
  const double x0 = x - align * w;
  cairo_set_font_size(c, font);
  cairo_move_to(c, x0, y);
  cairo_show_text(c, base.c_str());
  cairo_set_font_size(c, 0.72 * font);
  cairo_move_to(c, x0 + wb + 1, y - 0.45 * font);
  cairo_show_text(c, exp.c_str());
  cairo_set_font_size(c, font);
  return w;
}

void draw_text(cairo_t* c, double x, double y, const std::string& s, double align) {
  cairo_move_to(c, x - align * text_width(c, s), y);
  cairo_show_text(c, s.c_str());
}

void marker(cairo_t* c, int shape, double x, double y, double r) {
  switch (shape % 6) {
    case 0: cairo_arc(c, x, y, r, 0, 2 * M_PI); break;
    case 1: cairo_rectangle(c, x - 0.85 * r, y - 0.85 * r, 1.7 * r, 1.7 * r); break;
    case 2:
      cairo_move_to(c, x, y - 1.15 * r);
      cairo_line_to(c, x + r, y + 0.75 * r);
      cairo_line_to(c, x - r, y + 0.75 * r);
      cairo_close_path(c);
      break;
    case 3:
      cairo_move_to(c, x, y - 1.2 * r);
      cairo_line_to(c, x + 1.2 * r, y);
      cairo_line_to(c, x, y + 1.2 * r);
      cairo_line_to(c, x - 1.2 * r, y);
      cairo_close_path(c);
      break;
    case 4:
      cairo_move_to(c, x, y + 1.15 * r);
      cairo_line_to(c, x + r, y - 0.75 * r);
      cairo_line_to(c, x - r, y - 0.75 * r);
      cairo_close_path(c);
      break;
    default:
      cairo_move_to(c, x - r, y - r);
      cairo_line_to(c, x + r, y + r);
      cairo_move_to(c, x + r, y - r);
      cairo_line_to(c, x - r, y + r);
      cairo_set_line_width(c, 2.5);
      cairo_stroke(c);
      return;
  }
  cairo_fill_preserve(c);
  cairo_set_source_rgb(c, 0, 0, 0);
  cairo_set_line_width(c, 0.8);
  cairo_stroke(c);
}

bool has_error_bar(const PlotSeries& s, std::size_t i) {
  return i < s.y_low.size() && i < s.y_high.size() && std::isfinite(s.y_low[i]) && std::isfinite(s.y_high[i]);
}

void draw_panel(cairo_t* c, const PlotPanel& panel, double x0, double y0, double w, double h, double font) {
  // Ranges over all series (and the guides near the data).
  std::vector<double> xs, ys;
  for (const auto& s : panel.series)
    for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i) {
      xs.push_back(s.x[i]);
      ys.push_back(s.y[i]);
      if (has_error_bar(s, i)) {
        ys.push_back(s.y_low[i]);
        ys.push_back(s.y_high[i]);
      }
    }
  const Axis ax = make_axis(panel.log_x, xs);
  Axis ay = make_axis(panel.log_y, ys);
  std::vector<PlotGuide> guides;
  for (const auto& g : panel.guides)
    if (ay.drawable(g.y) && ay.frac(g.y) >= -1.0 && ay.frac(g.y) <= 2.0) guides.push_back(g);
  if (ys.empty()) guides.clear();
  if (!guides.empty()) {
    for (const auto& g : guides) ys.push_back(g.y);
    ay = make_axis(panel.log_y, ys);
  }

  const double left = x0 + 4.6 * font, right = x0 + w - 1.4 * font;
  const double top = y0 + 2.2 * font, bottom = y0 + h - 3.4 * font;
  const double pw = right - left, ph = bottom - top;
  auto X = [&](double v) { return left + ax.frac(v) * pw; };
  auto Y = [&](double v) { return bottom - ay.frac(v) * ph; };

  // Grid, ticks and tick labels.
  cairo_set_font_size(c, font);
  for (const Tick& t : ticks_of(ax)) {
    const double x = X(t.value);
    cairo_set_source_rgb(c, 0.88, 0.88, 0.88);
    cairo_set_line_width(c, t.major ? 1.0 : 0.6);
    cairo_move_to(c, x, top);
    cairo_line_to(c, x, bottom);
    cairo_stroke(c);
    cairo_set_source_rgb(c, 0, 0, 0);
    cairo_set_line_width(c, 1.0);
    cairo_move_to(c, x, bottom);
    cairo_line_to(c, x, bottom + (t.major ? 6 : 3));
    cairo_stroke(c);
    if (!t.major) continue;
    if (ax.log) draw_power(c, x, bottom + 8 + 1.1 * font, t.decade, font, 0.5);
    else draw_text(c, x, bottom + 8 + font, number_text(t.value), 0.5);
  }
  for (const Tick& t : ticks_of(ay)) {
    const double y = Y(t.value);
    cairo_set_source_rgb(c, 0.88, 0.88, 0.88);
    cairo_set_line_width(c, t.major ? 1.0 : 0.6);
    cairo_move_to(c, left, y);
    cairo_line_to(c, right, y);
    cairo_stroke(c);
    cairo_set_source_rgb(c, 0, 0, 0);
    cairo_set_line_width(c, 1.0);
    cairo_move_to(c, left, y);
    cairo_line_to(c, left - (t.major ? 6 : 3), y);
    cairo_stroke(c);
    if (!t.major) continue;
    if (ay.log) draw_power(c, left - 8, y + 0.35 * font, t.decade, font, 1.0);
    else draw_text(c, left - 8, y + 0.35 * font, number_text(t.value), 1.0);
  }

  // Frame, labels, title.
  cairo_set_source_rgb(c, 0, 0, 0);
  cairo_set_line_width(c, 1.2);
  cairo_rectangle(c, left, top, pw, ph);
  cairo_stroke(c);
  cairo_set_font_size(c, font);
  draw_text(c, left + pw / 2, y0 + h - 0.6 * font, panel.x_label, 0.5);
  cairo_save(c);
  cairo_move_to(c, x0 + 1.1 * font, top + ph / 2 + text_width(c, panel.y_label) / 2);
  cairo_rotate(c, -M_PI / 2);
  cairo_show_text(c, panel.y_label.c_str());
  cairo_restore(c);
  cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
  cairo_set_font_size(c, 1.05 * font);
  draw_text(c, left + pw / 2, y0 + 1.4 * font, panel.title, 0.5);
  cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(c, font);

  // Everything in data units is clipped to the plot area.
  cairo_save(c);
  cairo_rectangle(c, left, top, pw, ph);
  cairo_clip(c);
  const double dashes[] = {6, 4};
  for (const auto& g : guides) {
    cairo_set_source_rgb(c, 0.45, 0.45, 0.45);
    cairo_set_line_width(c, 1.0);
    cairo_set_dash(c, dashes, 2, 0);
    cairo_move_to(c, left, Y(g.y));
    cairo_line_to(c, right, Y(g.y));
    cairo_stroke(c);
    cairo_set_dash(c, nullptr, 0, 0);
    cairo_set_font_size(c, 0.8 * font);
    draw_text(c, left + 4, Y(g.y) - 3, g.label, 0.0);
    cairo_set_font_size(c, font);
  }
  for (std::size_t k = 0; k < panel.series.size(); ++k) {
    const PlotSeries& s = panel.series[k];
    const Rgb col = kPalette[k % kPaletteSize];
    const std::size_t n = std::min(s.x.size(), s.y.size());
    cairo_set_source_rgb(c, col.r, col.g, col.b);
    cairo_set_line_width(c, 2.0);
    bool pen = false;
    for (std::size_t i = 0; i < n; ++i) {
      if (!ax.drawable(s.x[i]) || !ay.drawable(s.y[i])) {
        pen = false;
        continue;
      }
      if (pen) cairo_line_to(c, X(s.x[i]), Y(s.y[i]));
      else cairo_move_to(c, X(s.x[i]), Y(s.y[i]));
      pen = true;
    }
    cairo_stroke(c);
    cairo_set_line_width(c, 1.4);
    for (std::size_t i = 0; i < n; ++i) {  // error bars with caps
      if (!has_error_bar(s, i) || !ax.drawable(s.x[i]) || !ay.drawable(s.y_low[i]) || !ay.drawable(s.y_high[i]))
        continue;
      const double x = X(s.x[i]), cap = 0.3 * font;
      cairo_move_to(c, x, Y(s.y_low[i]));
      cairo_line_to(c, x, Y(s.y_high[i]));
      for (double y : {Y(s.y_low[i]), Y(s.y_high[i])}) {
        cairo_move_to(c, x - cap, y);
        cairo_line_to(c, x + cap, y);
      }
      cairo_stroke(c);
    }
    for (std::size_t i = 0; i < n && s.markers; ++i) {
      if (!ax.drawable(s.x[i]) || !ay.drawable(s.y[i])) continue;
      cairo_set_source_rgb(c, col.r, col.g, col.b);
      marker(c, static_cast<int>(k), X(s.x[i]), Y(s.y[i]), 0.36 * font);
    }
  }
  if (xs.empty()) {
    cairo_set_source_rgb(c, 0.4, 0.4, 0.4);
    draw_text(c, left + pw / 2, top + ph / 2, "no data", 0.5);
  }
  cairo_restore(c);

  // Legend, top right inside the plot area.
  if (panel.series.empty()) return;
  double label_w = 0;
  for (const auto& s : panel.series) label_w = std::max(label_w, text_width(c, s.label));
  const double row = 1.35 * font, pad = 0.5 * font, sample_w = 2.4 * font;
  const double lw = pad * 3 + sample_w + label_w, lh = pad * 2 + row * static_cast<double>(panel.series.size());
  // In the corner that hides the fewest points (top right on a tie).
  double lx = 0, ly = 0;
  int fewest = -1;
  for (const auto& [cx, cy] : {std::pair{1, 0}, std::pair{0, 1}, std::pair{0, 0}, std::pair{1, 1}}) {
    const double x = cx ? right - lw - 0.5 * font : left + 0.5 * font;
    const double y = cy ? bottom - lh - 0.5 * font : top + 0.5 * font;
    int hidden = 0;
    for (const auto& s : panel.series)
      for (std::size_t i = 0; i < std::min(s.x.size(), s.y.size()); ++i)
        if (ax.drawable(s.x[i]) && ay.drawable(s.y[i]) && X(s.x[i]) > x - font && X(s.x[i]) < x + lw + font &&
            Y(s.y[i]) > y - font && Y(s.y[i]) < y + lh + font)
          ++hidden;
    if (fewest < 0 || hidden < fewest) {
      fewest = hidden;
      lx = x;
      ly = y;
    }
  }
  cairo_set_source_rgba(c, 1, 1, 1, 0.9);
  cairo_rectangle(c, lx, ly, lw, lh);
  cairo_fill_preserve(c);
  cairo_set_source_rgb(c, 0.5, 0.5, 0.5);
  cairo_set_line_width(c, 0.8);
  cairo_stroke(c);
  for (std::size_t k = 0; k < panel.series.size(); ++k) {
    const Rgb col = kPalette[k % kPaletteSize];
    const double cy = ly + pad + row * (static_cast<double>(k) + 0.5);
    cairo_set_source_rgb(c, col.r, col.g, col.b);
    cairo_set_line_width(c, 2.0);
    cairo_move_to(c, lx + pad, cy);
    cairo_line_to(c, lx + pad + sample_w, cy);
    cairo_stroke(c);
    if (panel.series[k].markers) marker(c, static_cast<int>(k), lx + pad + sample_w / 2, cy, 0.36 * font);
    cairo_set_source_rgb(c, 0, 0, 0);
    draw_text(c, lx + 2 * pad + sample_w, cy + 0.35 * font, panel.series[k].label, 0.0);
  }
}

}  // namespace

void draw_plot(cairo_t* c, const std::vector<PlotPanel>& panels, const PlotOptions& options) {
  cairo_set_source_rgb(c, 1, 1, 1);
  cairo_paint(c);
  cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
  const double font = options.font_px;
  double y0 = 0;
  if (!options.title.empty()) {
    cairo_set_source_rgb(c, 0, 0, 0);
    cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_BOLD);
    cairo_set_font_size(c, 1.15 * font);
    draw_text(c, options.width_px / 2.0, 1.5 * font, options.title, 0.5);
    cairo_select_font_face(c, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    y0 = 2.0 * font;
  }
  // Panels left to right, in rows of `columns` (all in one row if 0).
  const std::size_t columns = options.columns > 0 ? std::min(options.columns, std::max<std::size_t>(panels.size(), 1))
                                                  : std::max<std::size_t>(panels.size(), 1);
  const std::size_t rows = (panels.size() + columns - 1) / columns;
  const double pw = static_cast<double>(options.width_px) / static_cast<double>(columns);
  const double ph = (options.height_px - y0) / static_cast<double>(std::max<std::size_t>(rows, 1));
  for (std::size_t i = 0; i < panels.size(); ++i)
    draw_panel(c, panels[i], pw * static_cast<double>(i % columns), y0 + ph * static_cast<double>(i / columns), pw, ph,
               font);
}

}  // namespace fibrodem::cairo
