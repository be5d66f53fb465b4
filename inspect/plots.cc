// Plots with gnuplot: the gait diagram, per-leg bonded fraction and loads, the body's path.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "inspect/inspect.h"
#include "common/common.h"

namespace climbsim::inspect {
namespace {

// A gnuplot datablock "$name << EOD ... EOD" from rows of numbers.
class Block {
 public:
  explicit Block(std::string name) : name_(std::move(name)) {}
  void Add(std::initializer_list<double> row) {
    for (double v : row) {
      char buf[32];
      std::snprintf(buf, sizeof(buf), "%.9g ", v);
      text_ += buf;
    }
    text_ += "\n";
    ++rows_;
  }
  bool empty() const { return rows_ == 0; }
  const std::string& name() const { return name_; }
  std::string Define() const { return name_ + " << EOD\n" + text_ + "EOD\n"; }

 private:
  std::string name_;
  std::string text_;
  int rows_ = 0;
};

// Marks for detach causes: gnuplot point type and colour.
struct CauseStyle {
  int point_type;
  const char* colour;
};
CauseStyle DetachStyle(const std::string& cause) {
  if (cause == "peel") return {9, "#1565c0"};
  if (cause == "overload") return {7, "#c62828"};
  if (cause == "released") return {5, "#616161"};
  if (cause == "contact_lost") return {11, "#6a1b9a"};
  return {6, "#000000"};
}

// The script: datablocks once, then the same plot body for the PNG and the SVG.
std::string Script(const std::vector<const Block*>& blocks, const std::string& body, int width,
                   int height) {
  std::string s;
  for (const Block* b : blocks) s += b->Define();
  char term[256];
  std::snprintf(
      term, sizeof(term),
      "set terminal pngcairo size %d,%d noenhanced font \"sans,10\"\nset output OUTPUT(0)\n", width,
      height);
  s += term + body;
  std::snprintf(
      term, sizeof(term),
      "set terminal svg size %d,%d dynamic noenhanced font \"sans,10\"\nset output OUTPUT(1)\n",
      width, height);
  s += term + body + "unset output\n";
  return s;
}

// Draws `name`.png and `name`.svg in `out_dir`; a failed plot fails the verb, naming why.
void Run2(const std::string& script, const std::string& out_dir, const std::string& name,
          std::vector<std::string>* files) {
  const std::string error = common::RunGnuplot(out_dir, script, {name + ".png", name + ".svg"});
  if (!error.empty()) throw std::runtime_error("plot " + name + ": " + error);
  for (const char* ext : {".png", ".svg"}) files->push_back(out_dir + "/" + name + ext);
}

std::string Range(double a, double b) {
  char buf[96];
  std::snprintf(buf, sizeof(buf), "set xrange [%.9g:%.9g]\n", a, b);
  return buf;
}

// A panel with nothing to draw: gnuplot refuses `plot NaN` on an autoscaled axis ("all points
// y value undefined"), so the y range is fixed for it and restored to autoscale after.
std::string EmptyPanel(const std::string& what) {
  return "set yrange [0:1]\nset label 1 " + common::GnuplotQuote(what) +
         " at graph 0.5, graph 0.5 center\nplot NaN notitle\nunset label 1\nset autoscale y\n";
}

// Vertical lines at the pad's attach (green) and detach (red) inside the window.
std::string AttachDetachArrows(const Run& run, const std::string& pad, double a, double b) {
  std::string s = "unset arrow\n";
  char buf[160];
  for (const EventRow& e : run.events) {
    if (e.pad != pad || e.time_s < a || e.time_s > b) continue;
    const char* colour = e.event == "attach" ? "#2e7d32" : e.event == "detach" ? "#c62828" : "";
    if (*colour == 0) continue;
    std::snprintf(buf, sizeof(buf),
                  "set arrow from %.9g, graph 0 to %.9g, graph 1 nohead lc rgb \"%s\" dt 2\n",
                  e.time_s, e.time_s, colour);
    s += buf;
  }
  return s;
}

void GaitDiagram(const Run& run, const Report& report, const std::string& out_dir,
                 std::vector<std::string>* files) {
  const int n = static_cast<int>(report.legs.size());
  Block stances("$stances"), rejected("$rejected");
  std::map<std::string, Block> detaches;
  for (int i = 0; i < n; ++i) {
    const double y = n - 1 - i;  // first leg on top
    for (const Stance& s : report.legs[i].stances) stances.Add({s.start_s, s.end_s, y});
    for (const EventRow& e : run.events) {
      if (e.pad != report.legs[i].pad || e.time_s < report.from_s || e.time_s > report.to_s) {
        continue;
      }
      if (e.event == "attach_rejected") rejected.Add({e.time_s, y + 0.38});
      if (e.event == "detach") {
        const std::string cause = e.cause.empty() ? "unknown" : e.cause;
        detaches.try_emplace(cause, "$detach_" + std::to_string(detaches.size()));
        detaches.at(cause).Add({e.time_s, y});
      }
    }
  }
  std::string body = Range(report.from_s, report.to_s);
  char buf[256];
  std::snprintf(buf, sizeof(buf), "set yrange [-0.7:%d]\n", n);
  body += buf;
  body += "set ytics (";
  for (int i = 0; i < n; ++i) {
    body += (i ? ", " : "") + common::GnuplotQuote(report.legs[i].leg) + " " +
            std::to_string(n - 1 - i);
  }
  body += ")\nset xlabel \"time (s)\"\nset title " +
          common::GnuplotQuote("gait diagram: " + run.dir + "  (bar = pad attached)") +
          "\nset key outside right top\nset grid xtics\n";
  std::vector<std::string> plots;
  std::vector<const Block*> blocks;
  if (!stances.empty()) {
    plots.push_back(
        "$stances using (($1+$2)/2):3:(($2-$1)/2):(0.3) with boxxyerror fs solid 0.85 noborder "
        "lc rgb \"#66bb6a\" title \"attached\"");
    blocks.push_back(&stances);
  }
  if (!rejected.empty()) {
    plots.push_back(
        "$rejected using 1:2 with points pt 2 ps 1.2 lc rgb \"#e65100\" title \"attach "
        "rejected\"");
    blocks.push_back(&rejected);
  }
  for (const auto& [cause, block] : detaches) {
    const CauseStyle st = DetachStyle(cause);
    // The title is appended, not formatted into `buf`: a cut would leave its quote open.
    std::snprintf(buf, sizeof(buf), "%s using 1:2 with points pt %d ps 1.1 lc rgb \"%s\" title ",
                  block.name().c_str(), st.point_type, st.colour);
    plots.push_back(buf + common::GnuplotQuote("detach: " + cause));
    blocks.push_back(&block);
  }
  if (plots.empty()) plots.push_back("NaN title \"no attachments\"");
  body += "plot ";
  for (size_t i = 0; i < plots.size(); ++i) body += (i ? ", \\\n     " : "") + plots[i];
  body += "\n";
  Run2(Script(blocks, body, 1000, 120 + 60 * n), out_dir, "gait", files);
}

void PadPlot(const Run& run, const Report& report, const LegReport& leg, const std::string& out_dir,
             std::vector<std::string>* files, std::vector<std::string>* notes) {
  const double a = report.from_s, b = report.to_s;
  Block fraction("$fraction"), loads("$loads");
  const int column = run.trajectory ? run.trajectory->Column(leg.pad + "_bonded_fraction") : -1;
  bool from_events = false;
  if (column >= 0) {
    const NumericTable& t = *run.trajectory;
    for (size_t r = 0; r < t.rows(); ++r) {
      if (t.at(r, 0) >= a && t.at(r, 0) <= b) fraction.Add({t.at(r, 0), t.at(r, column)});
    }
  } else {
    from_events = true;
  }
  for (const EventRow& e : run.events) {
    if (e.pad != leg.pad || e.time_s < a || e.time_s > b) continue;
    loads.Add({e.time_s, e.fn_n, e.shear_n()});
    if (from_events) fraction.Add({e.time_s, e.bonded_fraction});
  }
  if (from_events && notes != nullptr) {
    notes->push_back("pad_" + leg.leg +
                     ": no bonded-fraction column in trajectory.csv; drawn from the events");
  }
  std::string body = Range(a, b);
  body += AttachDetachArrows(run, leg.pad, a, b);
  body += "set multiplot layout 2,1 title " +
          common::GnuplotQuote("leg " + leg.leg + " (" + leg.pad + "): " + run.dir +
                            "   green: attach, red: detach") +
          "\n";
  body += "set lmargin 10\nset rmargin 26\nset grid\nset key outside right top\n";
  body += "set ylabel \"bonded fraction\"\nset yrange [-0.05:1.05]\nunset xlabel\n";
  std::vector<const Block*> blocks;
  if (fraction.empty()) {
    body += EmptyPanel("no bonded fraction in this window");
  } else {
    blocks.push_back(&fraction);
    body += std::string("plot $fraction using 1:2 with ") + (from_events ? "steps" : "lines") +
            " lw 1.5 lc rgb \"#2e7d32\" title \"bonded\"\n";
  }
  body += "set ylabel \"pad load (N)\"\nset autoscale y\nset xlabel \"time (s)\"\n";
  if (loads.empty()) {
    body += EmptyPanel("no pad events in this window");
  } else {
    blocks.push_back(&loads);
    body +=
        "plot 0 notitle lc rgb \"#9e9e9e\", "
        "$loads using 1:2 with points pt 7 ps 0.6 lc rgb \"#1565c0\" title \"normal (+ pulls "
        "off)\", "
        "$loads using 1:3 with points pt 9 ps 0.6 lc rgb \"#e65100\" title \"shear\"\n";
  }
  body += "unset multiplot\n";
  Run2(Script(blocks, body, 1000, 560), out_dir, "pad_" + leg.leg, files);
}

// The base's path in the surface plane and its speed along the travel direction, both
// in the window, with the path's extent for the plot's ranges.
struct PathSeries {
  Block path{"$path"}, speed{"$speed"};
  double lat_lo = 0, lat_hi = 0, s_lo = 0, s_hi = 0;
};

PathSeries PathAndSpeed(const Run& run, const Report& report) {
  const NumericTable& t = *run.trajectory;
  const Eigen::Vector3d n(0, 0, 1);  // the surface normal of every scene (mjcf/README.md)
  Eigen::Vector3d along = run.travel - run.travel.dot(n) * n;
  if (along.norm() < 1e-9) along = Eigen::Vector3d::UnitX();
  const Eigen::Vector3d lateral = n.cross(along.normalized());
  const Eigen::Vector3d p0(t.at(0, 1), t.at(0, 2), t.at(0, 3));
  std::vector<double> time(t.rows()), s(t.rows());
  for (size_t r = 0; r < t.rows(); ++r) {
    time[r] = t.at(r, 0);
    s[r] = run.travel.dot(Eigen::Vector3d(t.at(r, 1), t.at(r, 2), t.at(r, 3)) - p0);
  }
  PathSeries out;
  constexpr double kHalfWindow = 0.25;  // s: the speed is a central difference over 0.5 s
  size_t lo = 0, hi = 0;
  for (size_t r = 0; r < t.rows(); ++r) {
    if (time[r] < report.from_s || time[r] > report.to_s) continue;
    const Eigen::Vector3d p = Eigen::Vector3d(t.at(r, 1), t.at(r, 2), t.at(r, 3)) - p0;
    out.path.Add({lateral.dot(p), s[r]});
    out.lat_lo = std::min(out.lat_lo, lateral.dot(p));
    out.lat_hi = std::max(out.lat_hi, lateral.dot(p));
    out.s_lo = std::min(out.s_lo, s[r]), out.s_hi = std::max(out.s_hi, s[r]);
    // Only where the whole window is recorded (no one-sided differences at the ends).
    if (time[r] - kHalfWindow < time.front() || time[r] + kHalfWindow > time.back()) continue;
    while (time[lo] < time[r] - kHalfWindow - 1e-9) ++lo;
    while (hi + 1 < t.rows() && time[hi + 1] <= time[r] + kHalfWindow + 1e-9) ++hi;
    if (time[hi] > time[lo]) out.speed.Add({time[r], (s[hi] - s[lo]) / (time[hi] - time[lo])});
  }
  return out;
}

// The left panel: the path on equal scales, a square whose side the larger span (or 1 cm)
// sets.
std::string PathPanel(const PathSeries& p, std::vector<const Block*>* blocks) {
  const double half = 0.55 * std::max({p.lat_hi - p.lat_lo, p.s_hi - p.s_lo, 0.01});
  char range[200];
  std::snprintf(range, sizeof(range), "set xrange [%.9g:%.9g]\nset yrange [%.9g:%.9g]\n",
                0.5 * (p.lat_lo + p.lat_hi) - half, 0.5 * (p.lat_lo + p.lat_hi) + half,
                0.5 * (p.s_lo + p.s_hi) - half, 0.5 * (p.s_lo + p.s_hi) + half);
  std::string body = range;
  body +=
      "set size ratio -1\nset xlabel \"lateral (m, left +)\"\nset ylabel \"along the travel "
      "direction (m)\"\nset title \"path of the base (start at 0)\"\n";
  if (p.path.empty()) {
    body += EmptyPanel("no trajectory rows in this window");
  } else {
    blocks->push_back(&p.path);
    body += "plot $path using 1:2 with lines lw 1.5 lc rgb \"#1565c0\" notitle\n";
  }
  return body;
}

// The right panel: the speed over time against the run's mean speed.
std::string SpeedPanel(const Run& run, const Report& report, const PathSeries& p,
                       std::vector<const Block*>* blocks) {
  const double mean = run.summary.value("mean_speed_mps", 0.0);
  std::string body = "set size noratio\nset autoscale y\n" + Range(report.from_s, report.to_s) +
                     "set xlabel \"time (s)\"\nset ylabel \"speed along the travel direction "
                     "(m/s)\"\nset title \"speed (central difference over 0.5 s)\"\n"
                     "set key bottom right\n";
  char buf[200];
  std::snprintf(buf, sizeof(buf), "%.9g dt 2 lc rgb \"#616161\" title \"run mean %.4f m/s\"", mean,
                mean);
  if (p.speed.empty()) {
    body += EmptyPanel("no speed: it needs 0.25 s of recording either side");
  } else {
    blocks->push_back(&p.speed);
    body += "plot $speed using 1:2 with lines lc rgb \"#2e7d32\" title \"speed\", " +
            std::string(buf) + "\n";
  }
  return body;
}

void PathPlot(const Run& run, const Report& report, const std::string& out_dir,
              std::vector<std::string>* files) {
  const PathSeries series = PathAndSpeed(run, report);
  std::vector<const Block*> blocks;
  std::string body =
      "set multiplot layout 1,2 title " + common::GnuplotQuote("body: " + run.dir) + "\nset grid\n";
  body += PathPanel(series, &blocks);
  body += SpeedPanel(run, report, series, &blocks);
  body += "unset multiplot\n";
  Run2(Script(blocks, body, 1100, 480), out_dir, "path", files);
}

}  // namespace

std::vector<std::string> WritePlots(const Run& run, const Report& report,
                                    const std::string& out_dir, std::vector<std::string>* notes) {
  std::vector<std::string> files;
  GaitDiagram(run, report, out_dir, &files);
  for (const LegReport& leg : report.legs) PadPlot(run, report, leg, out_dir, &files, notes);
  if (run.trajectory) {
    PathPlot(run, report, out_dir, &files);
  } else if (notes != nullptr) {
    notes->push_back("path: the run recorded no trajectory.csv; not drawn");
  }
  return files;
}

}  // namespace climbsim::inspect
