#include "report/report_html.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <tuple>
#include <vector>

namespace skidsim::report {
namespace {

using nlohmann::json;

constexpr int kMaxPlotPoints = 600;                       // per polyline, whatever the session's length
constexpr double kPlotW = 640, kPlotH = 150;              // SVG size in px
constexpr double kLeft = 70, kRight = 10, kTop = 8, kBottom = 22;  // room for the tick labels

// The report is read, not trusted: any key may be absent or of another type,
// so every look-up goes through here instead of operator[] / at() / value(),
// which throw (or insert) on a non-object.
const json& field(const json& j, const char* key) {
  static const json null_value;
  if (!j.is_object()) return null_value;
  const auto it = j.find(key);
  return it == j.end() ? null_value : *it;
}

std::optional<double> number(const json& j) {
  if (!j.is_number()) return std::nullopt;
  return j.get<double>();
}

std::string escape(const std::string& s) {
  std::string out;
  out.reserve(s.size());
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

std::string fmt(double v, const char* format = "%.6g") {
  if (!std::isfinite(v)) return "n/a";
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

// Any value as escaped text: strings as they are, integers exactly, floats
// to 6 significant digits; dump() replaces invalid UTF-8 instead of throwing.
std::string text(const json& j) {
  if (j.is_null()) return "";
  if (j.is_string()) return escape(j.get<std::string>());
  if (j.is_boolean()) return j.get<bool>() ? "yes" : "no";
  if (j.is_number_float()) return fmt(j.get<double>());
  return escape(j.dump(-1, ' ', false, json::error_handler_t::replace));
}

// Two columns, one row per member of an object (metrics, controls, ...).
void key_value_table(std::ostringstream& out, const json& obj) {
  if (!obj.is_object() || obj.empty()) return;
  out << "<table>";
  for (const auto& [key, value] : obj.items()) out << "<tr><th>" << escape(key) << "</th><td>" << text(value) << "</td></tr>";
  out << "</table>\n";
}

// The unit a timeline series' name ends with; longest suffixes first so that
// "_m_s" is not read as seconds.
std::pair<std::string, std::string> name_and_unit(const std::string& name) {
  static const std::pair<const char*, const char*> suffixes[] = {
      {"_m_s2", "m/s^2"}, {"_m_s", "m/s"}, {"_rad_s", "rad/s"}, {"_deg_s", "deg/s"}, {"_kg_s", "kg/s"},
      {"_rpm", "rpm"},   {"_kg", "kg"},   {"_deg", "deg"},     {"_rad", "rad"},     {"_kpa", "kPa"},
      {"_pa", "Pa"},     {"_kw", "kW"},   {"_n", "N"},         {"_m", "m"},         {"_s", "s"}};
  for (const auto& [suffix, unit] : suffixes) {
    const std::string sfx = suffix;
    if (name.size() > sfx.size() && name.compare(name.size() - sfx.size(), sfx.size(), sfx) == 0)
      return {name.substr(0, name.size() - sfx.size()), unit};
  }
  return {name, ""};
}

// The array as doubles when it is `n` finite numbers, else nothing (the
// series is skipped rather than drawn wrong).
std::optional<std::vector<double>> finite_series(const json& a, std::size_t n) {
  if (!a.is_array() || a.size() != n) return std::nullopt;
  std::vector<double> v;
  v.reserve(n);
  for (const json& x : a) {
    const std::optional<double> d = number(x);
    if (!d || !std::isfinite(*d)) return std::nullopt;
    v.push_back(*d);
  }
  return v;
}

// Indices to draw: all of them when few; else, per bucket of consecutive
// samples, its minimum and maximum in index order, so that short spikes (a
// tipping scare) survive the decimation. Deterministic: no sampling.
std::vector<std::size_t> decimate(const std::vector<double>& y) {
  std::vector<std::size_t> keep;
  const std::size_t n = y.size(), buckets = kMaxPlotPoints / 2;
  if (n <= static_cast<std::size_t>(kMaxPlotPoints)) {
    for (std::size_t i = 0; i < n; ++i) keep.push_back(i);
    return keep;
  }
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t i0 = b * n / buckets, i1 = (b + 1) * n / buckets;
    const auto [lo, hi] = std::minmax_element(y.begin() + static_cast<std::ptrdiff_t>(i0), y.begin() + static_cast<std::ptrdiff_t>(i1));
    const std::size_t a = static_cast<std::size_t>(lo - y.begin()), c = static_cast<std::size_t>(hi - y.begin());
    keep.push_back(std::min(a, c));
    if (a != c) keep.push_back(std::max(a, c));
  }
  return keep;
}

// A range to map onto the plot; a flat series gets some height so it draws
// as a line through the middle instead of dividing by zero.
std::pair<double, double> range_of(const std::vector<double>& v) {
  const auto [lo, hi] = std::minmax_element(v.begin(), v.end());
  if (*hi > *lo) return {*lo, *hi};
  const double pad = std::max(std::abs(*lo) * 0.05, 0.5);
  return {*lo - pad, *hi + pad};
}

void plot(std::ostringstream& out, const std::string& name, const std::vector<double>& t, const std::vector<double>& y,
          const json& events) {
  // Plain doubles, not structured bindings: C++17 lambdas cannot capture those.
  double t0, t1, y0, y1;
  std::tie(t0, t1) = range_of(t);
  std::tie(y0, y1) = range_of(y);
  const double w = kPlotW - kLeft - kRight, h = kPlotH - kTop - kBottom;
  const auto px = [&](double tv) { return fmt(kLeft + (tv - t0) / (t1 - t0) * w, "%.1f"); };
  const auto py = [&](double yv) { return fmt(kTop + (y1 - yv) / (y1 - y0) * h, "%.1f"); };
  const auto [base, unit] = name_and_unit(name);
  out << "<figure><figcaption>" << escape(base) << (unit.empty() ? "" : " (" + unit + ")") << "</figcaption>"
      << "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" << kPlotW << "\" height=\"" << kPlotH << "\" role=\"img\" aria-label=\""
      << escape(name) << "\">";
  // Axes and the min/max tick labels of both.
  out << "<path class=\"axis\" d=\"M" << kLeft << ',' << kTop << " V" << kTop + h << " H" << kLeft + w << "\"/>"
      << "<text x=\"" << kLeft - 4 << "\" y=\"" << kTop + 8 << "\" text-anchor=\"end\">" << fmt(y1, "%.4g") << "</text>"
      << "<text x=\"" << kLeft - 4 << "\" y=\"" << kTop + h << "\" text-anchor=\"end\">" << fmt(y0, "%.4g") << "</text>"
      << "<text x=\"" << kLeft << "\" y=\"" << kPlotH - 6 << "\">" << fmt(t0, "%.4g") << " s</text>"
      << "<text x=\"" << kLeft + w << "\" y=\"" << kPlotH - 6 << "\" text-anchor=\"end\">" << fmt(t1, "%.4g") << " s</text>";
  // Events that matter (severity >= 1) as vertical lines, their text as a tooltip.
  if (events.is_array()) {
    for (const json& e : events) {
      const std::optional<double> te = number(field(e, "time_s")), sev = number(field(e, "severity"));
      if (!te || !sev || *sev < 1 || !(*te >= t0 && *te <= t1)) continue;
      out << "<line class=\"" << (*sev >= 2 ? "ev2" : "ev1") << "\" x1=\"" << px(*te) << "\" x2=\"" << px(*te) << "\" y1=\""
          << kTop << "\" y2=\"" << kTop + h << "\"><title>" << fmt(*te, "%.2f") << " s: " << text(field(e, "text"))
          << "</title></line>";
    }
  }
  out << "<polyline points=\"";
  const std::vector<std::size_t> keep = decimate(y);
  for (std::size_t k = 0; k < keep.size(); ++k) out << (k ? " " : "") << px(t[keep[k]]) << ',' << py(y[keep[k]]);
  out << "\"/></svg></figure>\n";
}

void timeline(std::ostringstream& out, const json& tl, const json& events) {
  const json& t_json = field(tl, "t_s");
  if (!t_json.is_array() || t_json.empty()) return;
  const std::optional<std::vector<double>> t = finite_series(t_json, t_json.size());
  if (!t) return;
  out << "<h2>Timeline</h2>\n";
  for (const auto& [name, values] : tl.items()) {
    if (name == "t_s") continue;
    if (const std::optional<std::vector<double>> y = finite_series(values, t->size())) plot(out, name, *t, *y, events);
  }
}

const char* kStyle =
    "body{font-family:sans-serif;margin:1.5em;color:#222}table{border-collapse:collapse;margin:.5em 0}"
    "th,td{border:1px solid #ccc;padding:2px 8px;text-align:left}th{background:#f3f3f3}"
    ".banner{padding:.6em 1em;font-size:1.3em;font-weight:bold;color:#fff}.pass{background:#2a7d2a}"
    ".fail{background:#b22}.unknown{background:#777}figure{margin:.5em 0}figcaption{font-weight:bold}"
    "svg text{font-size:11px;fill:#444}.axis{fill:none;stroke:#444}polyline{fill:none;stroke:#1f5fbf;stroke-width:1.2}"
    ".ev1{stroke:#e08a00}.ev2{stroke:#d00}.sev1 td{background:#fff4e0}.sev2 td{background:#fde0e0}"
    "code{font-size:1.1em}";

}  // namespace

std::string render_report_html(const json& report) {
  std::ostringstream out;
  const json& exercise = field(report, "exercise");
  const json& result = field(report, "result");
  const std::string name = text(field(exercise, "name"));
  out << "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>skidsim report: " << name
      << "</title><style>" << kStyle << "</style></head><body>\n"
      << "<h1>" << (name.empty() ? "skidsim session" : name) << "</h1>\n";
  if (!field(exercise, "file").is_null()) out << "<p>Exercise file: <code>" << text(field(exercise, "file")) << "</code></p>\n";

  // The banner: pass/fail and the score against what passing takes.
  const json& passed = field(result, "passed");
  const char* cls = passed.is_boolean() ? (passed.get<bool>() ? "pass" : "fail") : "unknown";
  out << "<div class=\"banner " << cls << "\">"
      << (passed.is_boolean() ? (passed.get<bool>() ? "PASSED" : "NOT PASSED") : "NO RESULT");
  if (!field(result, "score").is_null())
    out << " &mdash; score " << text(field(result, "score")) << " (pass score " << text(field(result, "pass_score")) << ")";
  out << "</div>\n";

  json summary = json::object();
  for (const char* key : {"end_reason", "mode", "operator", "lockstep_missed_ticks", "machine_finite"})
    if (!field(report, key).is_null()) summary[key] = field(report, key);
  if (!field(result, "all_tasks_done").is_null()) summary["all_tasks_done"] = field(result, "all_tasks_done");
  const json& timed_out = field(result, "script_phases_timed_out");
  if (timed_out.is_array() && !timed_out.empty()) summary["script_phases_timed_out"] = timed_out;
  key_value_table(out, summary);

  const json& tasks = field(result, "tasks");
  if (tasks.is_array() && !tasks.empty()) {
    out << "<h2>Tasks</h2>\n<table><tr><th>id</th><th>type</th><th>done</th><th>done at</th><th>progress</th><th>detail</th></tr>";
    for (const json& task : tasks) {
      const std::optional<double> at = number(field(task, "done_at_s")), p = number(field(task, "progress"));
      out << "<tr><td>" << text(field(task, "id")) << "</td><td>" << text(field(task, "type")) << "</td><td>"
          << text(field(task, "done")) << "</td><td>" << (at && *at >= 0 ? fmt(*at, "%.2f") + " s" : "")  // -1: not done
          << "</td><td>" << (p ? fmt(*p * 100, "%.0f") + " %" : "") << "</td><td>" << text(field(task, "detail")) << "</td></tr>";
    }
    out << "</table>\n";
  }

  // The score, term by term.
  const json& breakdown = field(result, "score_breakdown");
  if (breakdown.is_array() && !breakdown.empty()) {
    out << "<h2>Score</h2>\n<table><tr><th>metric</th><th>value</th><th>weight</th><th>points</th></tr>";
    for (const json& b : breakdown)
      out << "<tr><td>" << text(field(b, "metric")) << "</td><td>" << text(field(b, "value")) << "</td><td>"
          << text(field(b, "weight")) << "</td><td>" << text(field(b, "points")) << "</td></tr>";
    out << "</table>\n";
  }

  // A strip of the recorded frames (frames/ beside this page), evenly spaced.
  const std::optional<double> frames = number(field(field(report, "recording"), "frames"));
  if (frames && *frames >= 1 && *frames < 1e9) {
    const auto n = static_cast<long long>(*frames);
    const long long shown = std::min<long long>(8, n);
    out << "<h2>Frames</h2>\n<p>";
    for (long long k = 0; k < shown; ++k) {
      char frame_name[40];
      std::snprintf(frame_name, sizeof frame_name, "frames/frame_%06lld.png", shown == 1 ? 0 : k * (n - 1) / (shown - 1));
      out << "<img src=\"" << frame_name << "\" width=\"200\" alt=\"" << frame_name << "\"> ";
    }
    out << "</p>\n";
  }

  const json& metrics = field(report, "metrics");
  const json& not_measured = field(report, "metrics_not_measured_yet");
  if (metrics.is_object() || not_measured.is_array()) out << "<h2>Metrics</h2>\n";
  key_value_table(out, metrics);
  if (not_measured.is_array() && !not_measured.empty()) {
    out << "<p>Not measured yet:";
    for (const json& m : not_measured) out << " <code>" << text(m) << "</code>";
    out << "</p>\n";
  }

  timeline(out, field(report, "timeline"), field(report, "events"));

  const json& events = field(report, "events");
  if (events.is_array() && !events.empty()) {
    out << "<h2>Events</h2>\n<table><tr><th>time</th><th>kind</th><th>severity</th><th>text</th></tr>";
    for (const json& e : events) {
      const std::optional<double> te = number(field(e, "time_s")), sev = number(field(e, "severity"));
      out << "<tr" << (sev && *sev >= 2 ? " class=\"sev2\"" : sev && *sev >= 1 ? " class=\"sev1\"" : "") << "><td>"
          << (te ? fmt(*te, "%.2f") + " s" : "") << "</td><td>" << text(field(e, "kind")) << "</td><td>"
          << text(field(e, "severity")) << "</td><td>" << text(field(e, "text")) << "</td></tr>";
    }
    out << "</table>\n";
  }

  const std::pair<const char*, const char*> sections[] = {
      {"controls", "Control inputs"}, {"performance", "Performance"}, {"files", "Files"}};
  for (const auto& [key, title] : sections) {
    const json& obj = field(report, key);
    if (!obj.is_object() || obj.empty()) continue;
    out << "<h2>" << title << "</h2>\n";
    key_value_table(out, obj);
  }
  if (!field(report, "final_state_hash").is_null())
    out << "<p>Final state hash: <code>" << text(field(report, "final_state_hash")) << "</code></p>\n";
  out << "</body></html>\n";
  return out.str();
}

}  // namespace skidsim::report
