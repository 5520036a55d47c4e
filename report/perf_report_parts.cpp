#include "report/perf_report_parts.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "io/soil_table.h"

namespace skidsim::report::perf {

nlohmann::json read_summary(const std::filesystem::path& dir) {
  std::ifstream in(dir / "summary.json");
  if (!in) throw std::runtime_error("performance report: no summary in " + dir.string());
  return nlohmann::json::parse(in);
}

std::size_t CsvNumbers::column(const std::string& name, const std::filesystem::path& path) const {
  for (std::size_t k = 0; k < header.size(); ++k)
    if (header[k] == name) return k;
  throw std::runtime_error("performance report: " + path.string() + " has no column '" + name + "'");
}

CsvNumbers read_csv_numbers(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("performance report: cannot read " + path.string());
  CsvNumbers out;
  std::string line;
  std::getline(in, line);
  for (std::stringstream ss(line); std::getline(ss, line, ',');) out.header.push_back(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> v;
    for (std::stringstream ss(line); std::getline(ss, line, ',');) v.push_back(std::stod(line));
    if (v.size() < out.header.size()) throw std::runtime_error("performance report: short row in " + path.string());
    out.rows.push_back(std::move(v));
  }
  return out;
}

std::filesystem::path repository_dem_dir() { return std::filesystem::path(io::default_assets_dir()).parent_path() / "dem"; }

std::map<std::string, double> read_csv_quantities(const std::filesystem::path& path, std::size_t value_column) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("performance report: cannot read " + path.string());
  std::map<std::string, double> out;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string c; std::getline(ss, c, ',');) cells.push_back(c);
    if (cells.size() <= value_column || cells[0].empty() || cells[0][0] == '#') continue;
    const std::string& text = cells[value_column];
    std::size_t used = 0;
    double v = 0.0;
    try {
      v = std::stod(text, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != text.size())
      throw std::runtime_error("performance report: " + path.string() + ": " + cells[0] + " is not a number: '" + text + "'");
    if (!out.emplace(cells[0], v).second)
      throw std::runtime_error("performance report: " + path.string() + ": " + cells[0] + " twice");
  }
  return out;
}

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

std::string svg_plot(const std::string& title, const std::string& error_label, const std::vector<Rung>& rungs,
                     const std::string& cost_label) {
  constexpr double W = 560, H = 340, L = 70, R = 20, T = 30, B = 50;
  // Errors below 1e-12 (round-off) sit on the axis's floor.
  constexpr double kFloor = 1e-12;
  double x0 = 1e300, x1 = -1e300, y0 = 1e300, y1 = -1e300;
  for (const Rung& r : rungs) {
    const double x = std::log10(std::max(r.cost, kFloor)), y = std::log10(std::max(r.error, kFloor));
    x0 = std::min(x0, x), x1 = std::max(x1, x), y0 = std::min(y0, y), y1 = std::max(y1, y);
  }
  x0 = std::floor(x0), x1 = std::max(std::ceil(x1), x0 + 1), y0 = std::floor(y0), y1 = std::max(std::ceil(y1), y0 + 1);
  const auto px = [&](double c) { return L + (W - L - R) * (std::log10(std::max(c, kFloor)) - x0) / (x1 - x0); };
  const auto py = [&](double e) { return H - B - (H - T - B) * (std::log10(std::max(e, kFloor)) - y0) / (y1 - y0); };
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H << "\" font-family=\"sans-serif\" font-size=\"11\">\n"
    << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << L << "\" y=\"18\" font-size=\"13\">" << title << "</text>\n"
    << "<rect x=\"" << L << "\" y=\"" << T << "\" width=\"" << W - L - R << "\" height=\"" << H - T - B
    << "\" fill=\"none\" stroke=\"#888\"/>\n";
  // A label per decade, at most about ten along an axis.
  const double x_every = std::ceil((x1 - x0) / 10.0), y_every = std::ceil((y1 - y0) / 10.0);
  for (double d = x0; d <= x1 + 1e-9; d += x_every)
    s << "<text x=\"" << L + (W - L - R) * (d - x0) / (x1 - x0) << "\" y=\"" << H - B + 14 << "\" text-anchor=\"middle\">1e"
      << static_cast<int>(d) << "</text>\n";
  for (double d = y0; d <= y1 + 1e-9; d += y_every)
    s << "<text x=\"" << L - 6 << "\" y=\"" << H - B - (H - T - B) * (d - y0) / (y1 - y0) + 4 << "\" text-anchor=\"end\">1e"
      << static_cast<int>(d) << "</text>\n";
  s << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">" << cost_label << "</text>\n"
    << "<text x=\"14\" y=\"" << (T + H - B) / 2 << "\" transform=\"rotate(-90 14 " << (T + H - B) / 2
    << ")\" text-anchor=\"middle\">" << error_label << "</text>\n<polyline fill=\"none\" stroke=\"#1f5fa8\" points=\"";
  for (const Rung& r : rungs) s << px(r.cost) << "," << py(r.error) << " ";
  s << "\"/>\n";
  for (const Rung& r : rungs)
    s << "<circle cx=\"" << px(r.cost) << "\" cy=\"" << py(r.error) << "\" r=\"4\" fill=\"#1f5fa8\"/><text x=\"" << px(r.cost) + 6
      << "\" y=\"" << py(r.error) - 6 << "\">" << r.label << "</text>\n";
  s << "</svg>\n";
  return s.str();
}

std::string svg_curves(const std::string& title, const std::string& x_label, const std::string& y_label,
                       const std::vector<Curve>& curves) {
  constexpr double W = 560, H = 340, L = 60, R = 150, T = 30, B = 50;
  static const char* kColours[] = {"#1f5fa8", "#c0392b", "#27ae60", "#8e44ad", "#d68910", "#17a589"};
  double x1 = 0.0, y1 = 0.0;
  for (const Curve& c : curves)
    for (const auto& [x, y] : c.points) x1 = std::max(x1, x), y1 = std::max(y1, y);
  // Axes from zero to a round top: 1, 2 or 5 times a power of ten per tick, five or so ticks.
  const auto nice = [](double top) {
    const double step = std::pow(10.0, std::floor(std::log10(std::max(top, 1e-12) / 5.0)));
    for (double m : {1.0, 2.0, 5.0, 10.0})
      if (top / (m * step) <= 6.0) return m * step;
    return 10.0 * step;
  };
  const double dx = nice(x1), dy = nice(y1);
  x1 = std::max(dx, std::ceil(x1 / dx) * dx), y1 = std::max(dy, std::ceil(y1 / dy) * dy);
  const auto px = [&](double x) { return L + (W - L - R) * x / x1; };
  const auto py = [&](double y) { return H - B - (H - T - B) * y / y1; };
  std::ostringstream s;
  s << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << W << "\" height=\"" << H
    << "\" font-family=\"sans-serif\" font-size=\"11\">\n<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n"
    << "<text x=\"" << L << "\" y=\"18\" font-size=\"13\">" << title << "</text>\n<rect x=\"" << L << "\" y=\"" << T
    << "\" width=\"" << W - L - R << "\" height=\"" << H - T - B << "\" fill=\"none\" stroke=\"#888\"/>\n";
  for (double x = 0.0; x <= x1 + 1e-9 * x1; x += dx)
    s << "<text x=\"" << px(x) << "\" y=\"" << H - B + 14 << "\" text-anchor=\"middle\">" << fmt("%g", x) << "</text>\n";
  for (double y = 0.0; y <= y1 + 1e-9 * y1; y += dy)
    s << "<text x=\"" << L - 6 << "\" y=\"" << py(y) + 4 << "\" text-anchor=\"end\">" << fmt("%g", y) << "</text>\n";
  s << "<text x=\"" << (L + W - R) / 2 << "\" y=\"" << H - 12 << "\" text-anchor=\"middle\">" << x_label << "</text>\n"
    << "<text x=\"14\" y=\"" << (T + H - B) / 2 << "\" transform=\"rotate(-90 14 " << (T + H - B) / 2
    << ")\" text-anchor=\"middle\">" << y_label << "</text>\n";
  int colour = -1;
  for (std::size_t k = 0; k < curves.size(); ++k) {
    const Curve& c = curves[k];
    if (!c.dashed || colour < 0) ++colour;
    const char* stroke = kColours[colour % 6];
    s << "<polyline fill=\"none\" stroke=\"" << stroke << "\"" << (c.dashed ? " stroke-dasharray=\"5,3\"" : "")
      << " points=\"";
    for (const auto& [x, y] : c.points) s << px(x) << "," << py(y) << " ";
    s << "\"/>\n";
    const double ly = T + 14.0 * (static_cast<double>(k) + 1.0);
    s << "<line x1=\"" << W - R + 8 << "\" y1=\"" << ly - 4 << "\" x2=\"" << W - R + 28 << "\" y2=\"" << ly - 4
      << "\" stroke=\"" << stroke << "\"" << (c.dashed ? " stroke-dasharray=\"5,3\"" : "") << "/><text x=\""
      << W - R + 32 << "\" y=\"" << ly << "\">" << c.name << "</text>\n";
  }
  s << "</svg>\n";
  return s.str();
}

std::string table(const std::vector<Rung>& rungs, const std::string& error_header, const std::string& cost_header,
                  const std::string& setting_header) {
  std::string t = "| " + setting_header + " | " + error_header + " | " + cost_header + " | |\n|---|---|---|---|\n";
  for (const Rung& r : rungs) t += "| " + r.label + " | " + fmt("%.4g", r.error) + " | " + fmt("%.4g", r.cost) + " | " + r.detail + " |\n";
  return t;
}

Convergence convergence(const std::vector<double>& sizes, const std::vector<Rung>& rungs, const std::string& what,
                        const std::string& shrinking) {
  Convergence c;
  const std::size_t n = std::min(sizes.size(), rungs.size());
  if (n < 2) {
    c.reading = "One rung only: no trend to read.";
    return c;
  }
  // Errors of exactly zero (a reference met to round-off) count as 1e-300.
  std::vector<double> le(n), lh(n);
  for (std::size_t k = 0; k < n; ++k) le[k] = std::log(std::max(rungs[k].error, 1e-300)), lh[k] = std::log(sizes[k]);
  bool every_falls = true;
  std::size_t worst_rise = 0;  // the rung after which the error rose most (0: none)
  double largest_rise = 0.0;
  for (std::size_t k = 1; k < n; ++k) {
    c.orders.push_back((le[k - 1] - le[k]) / (lh[k - 1] - lh[k]));
    if (le[k] >= le[k - 1]) every_falls = false;
    if (le[k] - le[k - 1] > largest_rise) largest_rise = le[k] - le[k - 1], worst_rise = k;
  }
  double mh = 0, me = 0;
  for (std::size_t k = 0; k < n; ++k) mh += lh[k] / n, me += le[k] / n;
  double sxy = 0, sxx = 0;
  for (std::size_t k = 0; k < n; ++k) sxy += (lh[k] - mh) * (le[k] - me), sxx += (lh[k] - mh) * (lh[k] - mh);
  c.fitted_order = sxx > 0 ? sxy / sxx : 0.0;  // e ~ h^p: p > 0 when the error falls with h
  const double hi = *std::max_element(le.begin(), le.end()), lo = *std::min_element(le.begin(), le.end());
  const double first = rungs.front().error, last = rungs[n - 1].error;
  // Falls: at every rung, by 1.5x or more in all. Falls overall / rises: the
  // fitted order beyond +-0.3 and the finest rung 1.5x below / above the
  // coarsest. Anything else wanders: flat.
  if (every_falls && le[0] - le[n - 1] >= std::log(1.5)) {
    c.trend = Trend::kFalls;
  } else if (c.fitted_order > 0.3 && le[0] - le[n - 1] >= std::log(1.5)) {
    c.trend = Trend::kFallsOverall;
  } else if (c.fitted_order < -0.3 && le[n - 1] - le[0] >= std::log(1.5)) {
    c.trend = Trend::kRises;
  } else {
    c.trend = Trend::kFlat;
  }
  std::string orders;
  for (std::size_t k = 0; k < c.orders.size(); ++k) orders += (k ? ", " : "") + fmt("%.2f", c.orders[k]);
  const std::string range = rungs.front().label + " to " + rungs[n - 1].label;
  switch (c.trend) {
    case Trend::kFalls:
      c.reading = "The " + what + " falls at every rung, from " + fmt("%.3g", first) + " to " + fmt("%.3g", last) + " (" + range +
                  "): observed order " + fmt("%.2f", c.fitted_order) + " over the ladder, " + fmt("%.2f", c.orders.back()) +
                  " between the last two rungs (orders rung to rung: " + orders + ").";
      break;
    case Trend::kFallsOverall:
      c.reading = "The " + what + " falls overall, from " + fmt("%.3g", first) + " to " + fmt("%.3g", last) + " (" + range +
                  "; fitted order " + fmt("%.2f", c.fitted_order) + "), but not at every rung: it rises from " +
                  fmt("%.3g", rungs[worst_rise - 1].error) + " at " + rungs[worst_rise - 1].label + " to " +
                  fmt("%.3g", rungs[worst_rise].error) + " at " + rungs[worst_rise].label + " (orders rung to rung: " + orders + ").";
      break;
    case Trend::kFlat:
      c.reading = "The " + what + " does not fall down the ladder (smaller " + shrinking + "): over " + range + " it stays between " +
                  fmt("%.3g", std::exp(lo)) + " and " + fmt("%.3g", std::exp(hi)) + " (fitted order " + fmt("%.2f", c.fitted_order) +
                  "; orders rung to rung: " + orders + ").";
      break;
    case Trend::kRises:
      c.reading = "The " + what + " grows down the ladder (smaller " + shrinking + "), from " + fmt("%.3g", first) + " to " + fmt("%.3g", last) + " (" +
                  range + "; fitted order " + fmt("%.2f", c.fitted_order) + "; orders rung to rung: " + orders + ").";
      break;
  }
  return c;
}

bool LadderBudget::allow(const std::string& label) {
  if (!stopped_ && wall_s_.size() >= 2) {
    const double last = wall_s_.back(), before = wall_s_[wall_s_.size() - 2];
    const double predicted = last * std::max(1.0, last / std::max(before, 1e-9));
    if (predicted > budget_s_) {
      stopped_ = true;
      skipped_.push_back(label + " (predicted " + fmt("%.0f", predicted) + " s from the last two rungs' " + fmt("%.2f", before) +
                         " s and " + fmt("%.2f", last) + " s, over the " + fmt("%.0f", budget_s_) + " s a rung may take)");
      return false;
    }
  }
  if (stopped_) {
    skipped_.push_back(label + " (finer than a skipped rung)");
    return false;
  }
  return true;
}

std::string LadderBudget::skipped_note() const {
  if (skipped_.empty()) return "";
  std::string s = "Skipped: ";
  for (std::size_t k = 0; k < skipped_.size(); ++k) s += (k ? "; " : "") + skipped_[k];
  return s + ".";
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace skidsim::report::perf
