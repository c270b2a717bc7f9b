#include "accuracy_plot.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "number_format.h"

namespace soltex::bench {
namespace {

constexpr double kWidth = 960, kHeight = 660;
constexpr double kFontSize = 11;
// DejaVu Sans, the usual fallback, averages about 0.6 em per character: wide enough that
// estimated label boxes do not undershoot the drawn text.
constexpr double kCharWidth = 0.6 * kFontSize;
constexpr const char* kFont = "DejaVu Sans, Helvetica, Arial, sans-serif";
constexpr const char* kFrontColour = "#c0392b";
constexpr const char* kOtherColour = "#7f8c8d";
constexpr const char* kPerPixelColour = "#2471a3";
constexpr const char* kBarColour = "#aab7b8";
constexpr const char* kInk = "#1b2631";

std::string escaped(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '&') {
      out += "&amp;";
    } else if (c == '<') {
      out += "&lt;";
    } else if (c == '>') {
      out += "&gt;";
    } else {
      out += c;
    }
  }
  return out;
}

std::string px(double v) {
  return fixed(v, 1);
}

struct Box {
  double x0, y0, x1, y1;
  double weight = 1.0;  // as an obstacle to labels: how much covering it costs per pixel

  double overlap(const Box& o) const {
    const double w = std::min(x1, o.x1) - std::max(x0, o.x0);
    const double h = std::min(y1, o.y1) - std::max(y0, o.y0);
    return w > 0 && h > 0 ? w * h : 0.0;
  }
  bool inside(const Box& o) const { return x0 >= o.x0 && x1 <= o.x1 && y0 >= o.y0 && y1 <= o.y1; }
  double width() const { return x1 - x0; }
  double height() const { return y1 - y0; }
};

// A value range with round tick marks (steps of 1, 2 or 5 times a power of ten), a little
// wider than the values so that no point sits on the frame.
struct Axis {
  double low, high, step;

  static Axis around(double min, double max, int ticks) {
    double span = max - min;
    if (!(span > 0)) span = std::max(std::abs(max) * 0.05, 0.1);
    min -= 0.08 * span;
    max += 0.08 * span;
    const double rough = (max - min) / ticks;
    const double power = std::pow(10.0, std::floor(std::log10(rough)));
    double step = power;
    for (double m : {1.0, 2.0, 5.0, 10.0}) {
      step = m * power;
      if (step >= rough) break;
    }
    return {std::floor(min / step) * step, std::ceil(max / step) * step, step};
  }
  double span() const { return high - low; }
  int decimals() const { return std::max(0, -static_cast<int>(std::floor(std::log10(step)))); }
};

// One point of the plot: a frame's median time with its quartiles, and its PSNR.
struct Mark {
  enum class Kind { front, other, per_pixel };
  double ms, q1, q3, psnr;
  std::string label;
  Kind kind;
};

// Data ranges drawn into a rectangle of the SVG.
struct Panel {
  Axis x, y;
  Box area;

  double to_x(double ms) const { return area.x0 + (ms - x.low) / x.span() * area.width(); }
  double to_y(double psnr) const { return area.y1 - (psnr - y.low) / y.span() * area.height(); }
  bool shows(const Mark& m) const {
    return m.ms >= x.low && m.ms <= x.high && m.psnr >= y.low && m.psnr <= y.high;
  }
  // What a mark covers in this panel: its marker and its quartile bar.
  std::vector<Box> covered_by(const Mark& m) const {
    const double cx = to_x(m.ms), cy = to_y(m.psnr);
    // Text may cross a thin bar and stay readable; it must not cover a marker.
    return {{cx - 7, cy - 7, cx + 7, cy + 7}, {to_x(m.q1), cy - 4, to_x(m.q3), cy + 4, 0.15}};
  }
};

std::string circle(double x, double y, double r, const char* colour) {
  return "<circle cx=\"" + px(x) + "\" cy=\"" + px(y) + "\" r=\"" + px(r) + "\" fill=\"" + colour +
         "\" stroke=\"white\" stroke-width=\"1.2\"/>\n";
}

// A square standing on a corner, `r` from the centre to each corner.
std::string diamond(double x, double y, double r, const char* colour) {
  return "<polygon points=\"" + px(x) + "," + px(y - r) + " " + px(x + r) + "," + px(y) + " " +
         px(x) + "," + px(y + r) + " " + px(x - r) + "," + px(y) + "\" fill=\"" + colour +
         "\" stroke=\"white\" stroke-width=\"1.2\"/>\n";
}

std::string text(double x, double y, const std::string& content, const std::string& attributes) {
  return "<text x=\"" + px(x) + "\" y=\"" + px(y) + "\" " + attributes + ">" + escaped(content) +
         "</text>\n";
}

struct Point {
  double x, y;
};

double distance(const Box& box, const Point& p) {
  const double dx = std::max({box.x0 - p.x, 0.0, p.x - box.x1});
  const double dy = std::max({box.y0 - p.y, 0.0, p.y - box.y1});
  return std::hypot(dx, dy);
}

// Finds each label a spot beside its point that covers no other label, point, bar or
// reserved area and is nearer its own point than any other: the first such spot of a few
// around the point, then farther out, else the least bad one. A label away from its point,
// or as near another point, gets a line to its own.
class LabelPlacer {
 public:
  struct Spot {
    double x, y;
    const char* anchor;
    bool leader;  // draw a line from the point to the label
    double cost;  // overlap in square pixels, plus a little per step away and for ambiguity
    Box box;
  };

  // `points`: every point drawn in `bounds`, the ones being labelled included.
  LabelPlacer(Box bounds, std::vector<Box> taken, std::vector<Point> points)
      : bounds_(bounds), taken_(std::move(taken)), points_(std::move(points)) {}

  Spot find(double x, double y, const std::string& label) const {
    struct Offset {
      double dx, dy;
      int anchor;  // -1 end, 0 middle, 1 start
    };
    static constexpr Offset kOffsets[] = {{10, 4, 1}, {-10, 4, -1}, {0, -11, 0},  {0, 19, 0},
                                          {9, -8, 1}, {9, 16, 1},   {-9, -8, -1}, {-9, 16, -1}};
    const double width = kCharWidth * static_cast<double>(label.size());
    Spot best{0, 0, "start", false, std::numeric_limits<double>::infinity(), {}};
    for (double reach : {1.0, 2.0, 3.0, 4.0}) {
      for (const Offset& o : kOffsets) {
        const double lx = x + o.dx * reach, ly = y + o.dy * reach;
        const double x0 = o.anchor == 1 ? lx : o.anchor == 0 ? lx - width / 2 : lx - width;
        const Box box{x0 - 1, ly - kFontSize + 1, x0 + width + 1, ly + 3};
        double cost = (reach - 1.0) * 10.0;
        for (const Box& t : taken_) cost += t.weight * t.overlap(box);
        if (!box.inside(bounds_)) cost += 1e6;
        const double own = distance(box, {x, y});
        bool ambiguous = false;
        for (const Point& p : points_) {
          const bool is_own = p.x == x && p.y == y;
          ambiguous = ambiguous || (!is_own && distance(box, p) <= own + 2.0);
        }
        cost += ambiguous ? 25.0 : 0.0;
        if (cost < best.cost) {
          const char* anchor = o.anchor == 1 ? "start" : o.anchor == 0 ? "middle" : "end";
          best = {lx, ly, anchor, reach > 1.0 || ambiguous, cost, box};
        }
      }
      if (best.cost < kCrowded) break;
    }
    return best;
  }

  // Places the label and returns its SVG.
  std::string place(double x, double y, const std::string& label, bool bold) {
    const Spot spot = find(x, y, label);
    taken_.push_back(spot.box);
    std::string svg;
    if (spot.leader) {
      svg += "<line x1=\"" + px(x) + "\" y1=\"" + px(y) + "\" x2=\"" +
             px(std::clamp(x, spot.box.x0, spot.box.x1)) + "\" y2=\"" +
             px(std::clamp(y, spot.box.y0, spot.box.y1)) +
             "\" stroke=\"#85929e\" stroke-width=\"1\"/>\n";
    }
    return svg + text(spot.x, spot.y, label,
                      std::string("text-anchor=\"") + spot.anchor + "\" fill=\"" +
                          (bold ? "#7b241c\" font-weight=\"bold\"" : "#4d5656\""));
  }

  // Below this a label overlaps nothing, is nearest its own point and stands close to it.
  static constexpr double kCrowded = 25.0;

 private:
  Box bounds_;
  std::vector<Box> taken_;
  std::vector<Point> points_;
};

// Grid lines and tick labels of a panel.
std::string grid(const Panel& p, double font_size) {
  std::string svg;
  const double eps_x = p.x.step / 2, eps_y = p.y.step / 2;
  for (double v = p.x.low; v <= p.x.high + eps_x; v += p.x.step) {
    const double x = p.to_x(v);
    svg += "<line x1=\"" + px(x) + "\" y1=\"" + px(p.area.y0) + "\" x2=\"" + px(x) + "\" y2=\"" +
           px(p.area.y1) + "\" stroke=\"#eaeded\"/>\n";
    svg += text(x, p.area.y1 + font_size + 5, fixed(v, p.x.decimals()),
                "text-anchor=\"middle\" fill=\"#424949\" font-size=\"" + px(font_size) + "\"");
  }
  for (double v = p.y.low; v <= p.y.high + eps_y; v += p.y.step) {
    const double y = p.to_y(v);
    svg += "<line x1=\"" + px(p.area.x0) + "\" y1=\"" + px(y) + "\" x2=\"" + px(p.area.x1) +
           "\" y2=\"" + px(y) + "\" stroke=\"#eaeded\"/>\n";
    svg += text(p.area.x0 - 6, y + font_size / 3, fixed(v, p.y.decimals()),
                "text-anchor=\"end\" fill=\"#424949\" font-size=\"" + px(font_size) + "\"");
  }
  svg += "<rect x=\"" + px(p.area.x0) + "\" y=\"" + px(p.area.y0) + "\" width=\"" +
         px(p.area.width()) + "\" height=\"" + px(p.area.height()) +
         "\" fill=\"none\" stroke=\"#839192\"/>\n";
  return svg;
}

// The part of segment a-b inside `box` (Liang-Barsky); false when none is. SVG clip paths
// would do, but not every renderer honours them.
bool clip_segment(const Box& box, double& ax, double& ay, double& bx, double& by) {
  double t0 = 0.0, t1 = 1.0;
  const double dx = bx - ax, dy = by - ay;
  const double p[] = {-dx, dx, -dy, dy};
  const double q[] = {ax - box.x0, box.x1 - ax, ay - box.y0, box.y1 - ay};
  for (int k = 0; k < 4; ++k) {
    if (p[k] == 0.0) {
      if (q[k] < 0.0) return false;
      continue;
    }
    const double t = q[k] / p[k];
    if (p[k] < 0.0) {
      t0 = std::max(t0, t);
    } else {
      t1 = std::min(t1, t);
    }
    if (t0 > t1) return false;
  }
  const double x0 = ax + t0 * dx, y0 = ay + t0 * dy;
  bx = ax + t1 * dx;
  by = ay + t1 * dy;
  ax = x0;
  ay = y0;
  return true;
}

// Quartile bars, the front's line and the markers of the points the panel shows, cut at its
// edges.
std::string data(const Panel& p, const std::vector<Mark>& marks) {
  std::string svg;
  for (const Mark& m : marks) {
    if (!p.shows(m)) continue;
    const double y = p.to_y(m.psnr);
    const double x1 = std::max(p.to_x(m.q1), p.area.x0), x3 = std::min(p.to_x(m.q3), p.area.x1);
    svg += "<path d=\"M" + px(x1) + " " + px(y - 4) + "v8M" + px(x1) + " " + px(y) + "H" + px(x3) +
           "M" + px(x3) + " " + px(y - 4) + "v8\" fill=\"none\" stroke=\"" + kBarColour +
           "\" stroke-width=\"1.2\"/>\n";
  }
  std::vector<const Mark*> front;
  for (const Mark& m : marks) {
    if (m.kind == Mark::Kind::front) front.push_back(&m);
  }
  std::sort(front.begin(), front.end(), [](const Mark* a, const Mark* b) { return a->ms < b->ms; });
  std::string line;
  for (std::size_t k = 1; k < front.size(); ++k) {
    double ax = p.to_x(front[k - 1]->ms), ay = p.to_y(front[k - 1]->psnr);
    double bx = p.to_x(front[k]->ms), by = p.to_y(front[k]->psnr);
    if (!clip_segment(p.area, ax, ay, bx, by)) continue;
    line += 'M';
    line += px(ax) + " " + px(ay) + "L" + px(bx) + " " + px(by);
  }
  if (!line.empty()) {
    svg += "<path d=\"" + line + "\" fill=\"none\" stroke=\"" + kFrontColour +
           "\" stroke-width=\"2\" stroke-linecap=\"round\"/>\n";
  }
  for (const Mark& m : marks) {
    if (!p.shows(m)) continue;
    const double x = p.to_x(m.ms), y = p.to_y(m.psnr);
    if (m.kind == Mark::Kind::other) svg += circle(x, y, 4.5, kOtherColour);
    if (m.kind == Mark::Kind::per_pixel) svg += diamond(x, y, 6.5, kPerPixelColour);
  }
  for (const Mark* m : front) {
    if (p.shows(*m)) svg += circle(p.to_x(m->ms), p.to_y(m->psnr), 6, kFrontColour);
  }
  return svg;
}

std::vector<Point> centres(const Panel& p, const std::vector<Mark>& marks) {
  std::vector<Point> points;
  for (const Mark& m : marks) {
    if (p.shows(m)) points.push_back({p.to_x(m.ms), p.to_y(m.psnr)});
  }
  return points;
}

std::vector<Box> covered_by_all(const Panel& p, const std::vector<Mark>& marks) {
  std::vector<Box> boxes;
  for (const Mark& m : marks) {
    for (const Box& b : p.covered_by(m)) boxes.push_back(b);
  }
  return boxes;
}

// Front labels first, so they get the best spots.
std::vector<const Mark*> label_order(const std::vector<Mark>& marks) {
  std::vector<const Mark*> order;
  for (const Mark& m : marks) order.push_back(&m);
  std::stable_sort(order.begin(), order.end(), [](const Mark* a, const Mark* b) {
    return a->kind == Mark::Kind::front && b->kind != Mark::Kind::front;
  });
  return order;
}

// A magnified view of the points that crowd each other in the main panel, in a corner of it
// that holds no point; absent when nothing is crowded or no corner is free.
struct Inset {
  Panel panel;  // the magnified ranges, drawn into the inset's inner area
  Box outer;    // the inset with its tick labels
};

std::optional<Inset> inset_for(const Panel& main, const std::vector<Mark>& marks) {
  // The points with another one so close that a label between them could belong to either...
  constexpr double kClose = 30.0;
  std::vector<const Mark*> crowded;
  for (const Mark& a : marks) {
    for (const Mark& b : marks) {
      if (&a != &b && std::hypot(main.to_x(a.ms) - main.to_x(b.ms),
                                 main.to_y(a.psnr) - main.to_y(b.psnr)) < kClose) {
        crowded.push_back(&a);
        break;
      }
    }
  }
  // ...and the densest group around one of them: the points within a window a sixth of the
  // panel wide and high.
  const double reach_x = main.area.width() / 6, reach_y = main.area.height() / 6;
  const auto near = [&](const Mark& a, const Mark& b) {
    return std::abs(main.to_x(a.ms) - main.to_x(b.ms)) <= reach_x &&
           std::abs(main.to_y(a.psnr) - main.to_y(b.psnr)) <= reach_y;
  };
  std::vector<const Mark*> group;
  for (const Mark* c : crowded) {
    std::vector<const Mark*> around;
    for (const Mark& m : marks) {
      if (near(*c, m)) around.push_back(&m);
    }
    if (around.size() > group.size()) group = std::move(around);
  }
  if (group.size() < 3) return std::nullopt;
  double ms_min = std::numeric_limits<double>::infinity(), ms_max = -ms_min;
  double psnr_min = ms_min, psnr_max = -ms_min;
  for (const Mark* m : group) {
    ms_min = std::min(ms_min, m->ms);
    ms_max = std::max(ms_max, m->ms);
    psnr_min = std::min(psnr_min, m->psnr);
    psnr_max = std::max(psnr_max, m->psnr);
  }
  Panel zoom{Axis::around(ms_min, ms_max, 4), Axis::around(psnr_min, psnr_max, 4), {}};
  const Box zoom_box{main.to_x(zoom.x.low), main.to_y(zoom.y.high), main.to_x(zoom.x.high),
                     main.to_y(zoom.y.low)};
  const std::vector<Box> covered = covered_by_all(main, marks);
  const Box& a = main.area;
  constexpr double kMargin = 10, kLeftTicks = 40, kBottomTicks = 20;
  // The largest inset that fits a free corner, down to a third of the panel.
  for (double share : {0.5, 0.42, 0.34}) {
    const double w = share * a.width(), h = share * a.height();
    // Magnifying less than twice would not untangle anything.
    if (zoom_box.width() > w / 2 && zoom_box.height() > h / 2) return std::nullopt;
    const Box corners[] = {
        {a.x1 - kMargin - w, a.y1 - kMargin - h, a.x1 - kMargin, a.y1 - kMargin},
        {a.x0 + kMargin, a.y1 - kMargin - h, a.x0 + kMargin + w, a.y1 - kMargin},
        {a.x1 - kMargin - w, a.y0 + kMargin, a.x1 - kMargin, a.y0 + kMargin + h},
        {a.x0 + kMargin, a.y0 + kMargin, a.x0 + kMargin + w, a.y0 + kMargin + h}};
    for (const Box& outer : corners) {
      bool free = outer.overlap(zoom_box) == 0.0;
      for (const Box& b : covered) free = free && outer.overlap(b) == 0.0;
      if (!free) continue;
      zoom.area = {outer.x0 + kLeftTicks, outer.y0 + 10, outer.x1 - 10, outer.y1 - kBottomTicks};
      return Inset{zoom, outer};
    }
  }
  return std::nullopt;
}

// The label of a frame: its first setting's, and the codecs that draw the same frame.
std::string frame_label(const AccuracyRun& run, std::size_t leader) {
  std::string label = run.results[leader].setting.label();
  std::string also;
  for (std::size_t i = leader + 1; i < run.results.size(); ++i) {
    if (run.results[i].frame_group != static_cast<int>(leader)) continue;
    if (!also.empty()) also += '/';
    also += run.results[i].setting.codec.name();
  }
  return also.empty() ? label : label + " (also " + also + ")";
}

}  // namespace

void write_plot(const AccuracyRun& run, const std::filesystem::path& path) {
  const bool cpu = run.options.front_clock == FrameClock::cpu;
  std::vector<Mark> marks;
  for (std::size_t i = 0; i < run.results.size(); ++i) {
    const SettingResult& r = run.results[i];
    if (r.frame_group != static_cast<int>(i)) continue;
    const FrameTime& t = front_time(r, run.options.front_clock);
    marks.push_back({t.median_ms, t.q1_ms, t.q3_ms, r.error.psnr_db, frame_label(run, i),
                     r.on_front ? Mark::Kind::front : Mark::Kind::other});
  }
  const FrameTime& pp = per_pixel_front_time(run);
  marks.push_back({pp.median_ms, pp.q1_ms, pp.q3_ms, run.per_pixel_error.psnr_db,
                   "per-pixel evaluation, no cache", Mark::Kind::per_pixel});

  double ms_min = std::numeric_limits<double>::infinity(), ms_max = -ms_min;
  double psnr_min = ms_min, psnr_max = -ms_min;
  for (const Mark& m : marks) {
    ms_min = std::min(ms_min, m.q1);
    ms_max = std::max(ms_max, m.q3);
    psnr_min = std::min(psnr_min, m.psnr);
    psnr_max = std::max(psnr_max, m.psnr);
  }
  const Panel main{Axis::around(ms_min, ms_max, 6),
                   Axis::around(psnr_min, psnr_max, 6),
                   {80, 86, kWidth - 30, kHeight - 92}};
  const std::optional<Inset> inset = inset_for(main, marks);

  std::ostringstream svg;
  svg << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kWidth << "\" height=\"" << kHeight
      << "\" viewBox=\"0 0 " << kWidth << " " << kHeight << "\" font-family=\"" << kFont
      << "\" font-size=\"" << kFontSize << "\">\n"
      << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
      << text(main.area.x0, 26,
              "What accuracy costs: " + run.scene_name + ", " +
                  std::to_string(run.options.size.width) + "x" +
                  std::to_string(run.options.size.height),
              std::string("font-size=\"17\" font-weight=\"bold\" fill=\"") + kInk + "\"")
      << text(main.area.x0, 44,
              "PSNR against per-pixel evaluation, " + std::to_string(run.reference_supersample) +
                  "x" + std::to_string(run.reference_supersample) + " supersampled.",
              "fill=\"#566573\"")
      << text(main.area.x0, 58,
              std::string("Frame time: median of warm frames (") +
                  (cpu ? "CPU time, every render thread summed" : "wall time") +
                  "), bars from first to third quartile.",
              "fill=\"#566573\"")
      << text(main.area.x0, 72,
              "Shared machine: " + run.machine + "; 1-minute load average " +
                  fixed(run.load_before, 1) + " at the start, " + fixed(run.load_after, 1) +
                  " at the end.",
              "fill=\"#566573\"")
      << grid(main, kFontSize)
      << text((main.area.x0 + main.area.x1) / 2, main.area.y1 + 40,
              std::string(cpu ? "CPU time" : "wall time") + " per warm frame, ms (left is faster)",
              std::string("text-anchor=\"middle\" font-size=\"13\" fill=\"") + kInk + "\"")
      << "<text transform=\"translate(24 " << px((main.area.y0 + main.area.y1) / 2)
      << ") rotate(-90)\" text-anchor=\"middle\" font-size=\"13\" fill=\"" << kInk
      << "\">PSNR, dB (up is more accurate)</text>\n"
      << data(main, marks);

  // Labels in the main panel, except for the points the inset magnifies.
  std::vector<Box> reserved = covered_by_all(main, marks);
  if (inset) {
    const Panel& z = inset->panel;
    const Box zoom_box{main.to_x(z.x.low), main.to_y(z.y.high), main.to_x(z.x.high),
                       main.to_y(z.y.low)};
    reserved.push_back(inset->outer);
    reserved.push_back(zoom_box);
    svg << "<rect x=\"" << px(zoom_box.x0) << "\" y=\"" << px(zoom_box.y0) << "\" width=\""
        << px(zoom_box.width()) << "\" height=\"" << px(zoom_box.height())
        << "\" fill=\"none\" stroke=\"#5d6d7e\" stroke-dasharray=\"4 3\"/>\n";
  }
  LabelPlacer main_labels(main.area, reserved, centres(main, marks));
  for (const Mark* m : label_order(marks)) {
    if (inset && inset->panel.shows(*m)) continue;
    svg << main_labels.place(main.to_x(m->ms), main.to_y(m->psnr), m->label,
                             m->kind == Mark::Kind::front);
  }

  if (inset) {
    const Panel& z = inset->panel;
    const Box& o = inset->outer;
    svg << "<rect x=\"" << px(o.x0) << "\" y=\"" << px(o.y0) << "\" width=\"" << px(o.width())
        << "\" height=\"" << px(o.height())
        << "\" fill=\"white\" stroke=\"#5d6d7e\" stroke-dasharray=\"4 3\"/>\n"
        << grid(z, 10) << data(z, marks);
    LabelPlacer inset_labels(z.area, covered_by_all(z, marks), centres(z, marks));
    for (const Mark* m : label_order(marks)) {
      if (!z.shows(*m)) continue;
      svg << inset_labels.place(z.to_x(m->ms), z.to_y(m->psnr), m->label,
                                m->kind == Mark::Kind::front);
    }
    svg << text(o.x0 + 6, o.y0 - 4, "magnified: the dashed box", "fill=\"#5d6d7e\"");
  }

  // Legend, under the axis title: each entry a marker and its text, one after the other.
  const double ly = main.area.y1 + 68;
  double lx = main.area.x0;
  const auto entry = [&](const std::string& marker, const std::string& label) {
    svg << marker << text(lx + 14, ly + 4, label, std::string("fill=\"") + kInk + "\"");
    lx += 14 + kCharWidth * static_cast<double>(label.size()) + 22;
  };
  entry("<line x1=\"" + px(lx - 8) + "\" y1=\"" + px(ly) + "\" x2=\"" + px(lx + 8) + "\" y2=\"" +
            px(ly) + "\" stroke=\"" + kFrontColour + "\" stroke-width=\"2\"/>" +
            circle(lx, ly, 6, kFrontColour),
        "Pareto front: nothing else is both faster and more accurate");
  entry(circle(lx, ly, 4.5, kOtherColour), "other settings");
  entry(diamond(lx, ly, 6.5, kPerPixelColour), "no cache, for scale");
  svg << "</svg>\n";

  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream out(path);
  out << svg.str();
  out.close();
  if (!out) throw std::runtime_error("cannot write " + path.string());
}

}  // namespace soltex::bench
