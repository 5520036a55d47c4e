// The session's HTML report: banner, tasks, metrics, one plot per timeline
// series (skipping broken series, capping the points drawn), all report text
// escaped, and nothing thrown for missing or mistyped keys.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "report/report_html.h"

namespace skidsim::report {
namespace {

using nlohmann::json;

std::size_t count(const std::string& haystack, const std::string& needle) {
  std::size_t n = 0;
  for (std::size_t at = haystack.find(needle); at != std::string::npos; at = haystack.find(needle, at + needle.size())) ++n;
  return n;
}

// The "x,y" pairs of every polyline in the page, one vector per polyline.
std::vector<std::vector<std::pair<double, double>>> polylines(const std::string& html) {
  std::vector<std::vector<std::pair<double, double>>> lines;
  const std::string open = "<polyline points=\"";
  for (std::size_t at = html.find(open); at != std::string::npos; at = html.find(open, at + 1)) {
    const std::size_t begin = at + open.size(), end = html.find('"', begin);
    std::istringstream points(html.substr(begin, end - begin));
    std::vector<std::pair<double, double>> line;
    std::string point;
    while (points >> point) {
      const std::size_t comma = point.find(',');
      line.emplace_back(std::stod(point.substr(0, comma)), std::stod(point.substr(comma + 1)));
    }
    lines.push_back(line);
  }
  return lines;
}

json synthetic_report() {
  json timeline = {{"t_s", json::array()},           {"speed_m_s", json::array()},         {"bucket_payload_kg", json::array()},
                   {"score", json::array()},         {"task_progress", json::array()},     {"engine_speed_rpm", json::array()},
                   {"tipping_margin", json::array()}, {"material_moved_kg", json::array()}};
  for (int i = 0; i <= 200; ++i) {
    const double t = 0.5 * i;
    timeline["t_s"].push_back(t);
    timeline["speed_m_s"].push_back(1.5 * std::sin(0.1 * t));
    timeline["bucket_payload_kg"].push_back(i % 50 * 4.0);
    timeline["score"].push_back(0.8 * i);
    timeline["task_progress"].push_back(i / 200.0);
    timeline["engine_speed_rpm"].push_back(2400.0);  // flat: must still plot
    timeline["tipping_margin"].push_back(0.6 + 0.1 * std::cos(t));
    timeline["material_moved_kg"].push_back(4.0 * i);
  }
  return {
      {"exercise", {{"name", "Pile <to> zone & back"}, {"file", "scenarios/pile_to_zone.xml"}}},
      {"mode", "lockstep"},
      {"operator", "script scenarios/pile_to_zone.ops"},
      {"result",
       {{"passed", true},
        {"score", 87.5},
        {"pass_score", 60},
        {"all_tasks_done", true},
        {"tasks",
         {{{"id", "fill_bucket"}, {"type", "dig"}, {"done", true}, {"done_at_s", 40.25}, {"progress", 1.0}, {"detail", "full"}},
          {{"id", "deliver_target"}, {"type", "deliver"}, {"done", false}, {"done_at_s", -1.0}, {"progress", 0.612},
           {"detail", "612 of 1000 kg in 'target'"}}}},
        {"script_phases_timed_out", json::array()}}},
      {"metrics", {{"completion_time_s", 126.0}, {"material_moved_kg", 801.2}, {"idle_time_s", 3.5}}},
      {"metrics_not_measured_yet", {"fuel_used_l"}},
      {"events",
       {{{"time_s", 12.5}, {"kind", "message"}, {"severity", 0}, {"text", "go"}},
        {{"time_s", 50.0}, {"kind", "warning"}, {"severity", 2}, {"text", "tip <script>&\" now"}},
        {{"time_s", 70.0}, {"kind", "watchdog"}, {"severity", 1}, {"text", "no command"}}}},
      {"controls", {{"accepted", 12600}, {"clamped", 3}, {"rejected_nan", 0}, {"rejected_stale", 0}, {"malformed", 0},
                    {"watchdog_trips", 1}}},
      {"final_state_hash", "0123456789abcdef"},
      {"end_reason", "all_tasks_done"},
      {"lockstep_missed_ticks", 0},
      {"machine_finite", true},
      {"performance", {{"simulated_s", 100.0}, {"wall_time_s", 9.5}, {"real_time_factor", 10.5}}},
      {"files", {{"lcm_log", "session.lcmlog"}, {"terrain", "terrain_surface.png"}}},
      {"timeline", timeline},
  };
}

TEST(ReportHtml, ShowsBannerTasksMetricsAndOnePlotPerSeries) {
  const std::string html = render_report_html(synthetic_report());
  EXPECT_EQ(html.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_NE(html.find("class=\"banner pass\">PASSED"), std::string::npos);
  EXPECT_NE(html.find("score 87.5 (pass score 60)"), std::string::npos);
  for (const char* s : {"fill_bucket", "deliver_target", "612 of 1000 kg in &#39;target&#39;", "61 %", "40.25 s", "all_tasks_done",
                        "lockstep", "completion_time_s", "material_moved_kg", "idle_time_s", "fuel_used_l", "12600",
                        "real_time_factor", "0123456789abcdef"})
    EXPECT_NE(html.find(s), std::string::npos) << s;
  EXPECT_EQ(count(html, "<polyline"), 7u);
  for (const char* caption : {"speed (m/s)", "bucket_payload (kg)", "engine_speed (rpm)", "tipping_margin<", "score<"})
    EXPECT_NE(html.find(caption), std::string::npos) << caption;
  for (const auto& line : polylines(html)) EXPECT_EQ(line.size(), 201u);
  // Events of severity >= 1 (two of them, inside the time range) on every plot; severity 0 not.
  EXPECT_EQ(count(html, "<line class=\"ev"), 2u * 7u);
  EXPECT_EQ(html.find("<script"), std::string::npos) << "no scripts in the page";
  EXPECT_EQ(html, render_report_html(synthetic_report())) << "deterministic";
}

TEST(ReportHtml, EscapesAllReportText) {
  const std::string html = render_report_html(synthetic_report());
  EXPECT_NE(html.find("tip &lt;script&gt;&amp;&quot; now"), std::string::npos);
  EXPECT_EQ(html.find("<script"), std::string::npos);
  EXPECT_EQ(html.find("&\" now"), std::string::npos);
  EXPECT_NE(html.find("<h1>Pile &lt;to&gt; zone &amp; back</h1>"), std::string::npos);
  EXPECT_EQ(html.find("<to>"), std::string::npos);
}

TEST(ReportHtml, NoTimelineMeansNoPlotsAndMissingKeysDoNotThrow) {
  json report = synthetic_report();
  report.erase("timeline");
  std::string html;
  ASSERT_NO_THROW(html = render_report_html(report));
  EXPECT_EQ(html.find("<svg"), std::string::npos);
  EXPECT_NE(html.find("fill_bucket"), std::string::npos);

  report["timeline"] = json::object();
  ASSERT_NO_THROW(html = render_report_html(report));
  EXPECT_EQ(html.find("<svg"), std::string::npos);
  report["timeline"] = {{"t_s", json::array()}, {"speed_m_s", json::array()}};
  ASSERT_NO_THROW(html = render_report_html(report));
  EXPECT_EQ(html.find("<svg"), std::string::npos);

  // Empty, wrongly typed and half-filled reports render what they have.
  const json odd[] = {json(), json::array(), json(42), json::object(),
                      {{"result", "passed"}, {"events", {1, "a", {{"time_s", "x"}}}}, {"metrics", {1, 2}}},
                      {{"exercise", {{"name", 3}}}, {"result", {{"tasks", {{{"id", 7}}, "x"}}}}, {"timeline", {1, 2}}},
                      {{"timeline", {{"t_s", {0, 1}}, {"v_m", {1, 2}}}}, {"events", {{{"time_s", 0.5}, {"severity", "high"}}}}}};
  for (const json& r : odd) {
    ASSERT_NO_THROW(html = render_report_html(r)) << r.dump();
    EXPECT_NE(html.find("</html>"), std::string::npos);
  }
  EXPECT_NE(render_report_html(json::object()).find("NO RESULT"), std::string::npos);
}

TEST(ReportHtml, SkipsMismatchedAndNonFiniteSeries) {
  json report = synthetic_report();
  report["timeline"]["short_kg"] = {1.0, 2.0, 3.0};
  report["timeline"]["broken_m"] = report["timeline"]["score"];
  report["timeline"]["broken_m"][17] = std::numeric_limits<double>::quiet_NaN();
  report["timeline"]["words"] = report["timeline"]["score"];
  report["timeline"]["words"][3] = "three";
  const std::string html = render_report_html(report);
  EXPECT_EQ(count(html, "<polyline"), 7u);
  EXPECT_EQ(html.find("short"), std::string::npos);
  EXPECT_EQ(html.find("broken"), std::string::npos);
  EXPECT_EQ(html.find("words"), std::string::npos);

  // A broken time axis: no plots at all.
  report["timeline"]["t_s"][5] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(count(render_report_html(report), "<polyline"), 0u);
}

TEST(ReportHtml, DecimationCapsPointsAndKeepsSpikes) {
  constexpr int n = 100000;
  json t = json::array(), y = json::array();
  for (int i = 0; i < n; ++i) {
    t.push_back(0.01 * i);
    y.push_back(i == 54321 ? 1000.0 : std::sin(0.001 * i));  // one sample's spike
  }
  const json report = {{"timeline", {{"t_s", t}, {"load_kg", y}}}};
  const std::string html = render_report_html(report);
  const auto lines = polylines(html);
  ASSERT_EQ(lines.size(), 1u);
  EXPECT_LE(lines[0].size(), 601u);
  EXPECT_GE(lines[0].size(), 300u);
  double top = 1e9, left = 1e9, right = -1e9, previous_x = -1e9;
  for (const auto& [x, py] : lines[0]) {
    top = std::min(top, py);
    left = std::min(left, x);
    right = std::max(right, x);
    EXPECT_GE(x, previous_x) << "points in time order";
    previous_x = x;
  }
  EXPECT_NEAR(top, 8.0, 0.05) << "the one-sample spike reaches the top of the plot";
  EXPECT_LT(left, 71.0);   // spans the plot: starts near the y axis ...
  EXPECT_GT(right, 629.0);  // ... and ends near the right edge
  EXPECT_EQ(html, render_report_html(report)) << "deterministic";
}

// The score term by term, and a strip of 8 frames spread over a recording.
TEST(ReportHtml, ShowsTheScoreBreakdownAndAStripOfFrames) {
  json report = synthetic_report();
  report["result"]["score_breakdown"] = json::array({{{"metric", "material_moved_kg"}, {"weight", 0.05}, {"value", 800.0}, {"points", 40.0}}});
  report["recording"] = {{"frames", 100}, {"fps", 10.0}, {"camera", "chase"}, {"dir", "frames"}};
  const std::string html = render_report_html(report);
  EXPECT_NE(html.find("<h2>Score</h2>"), std::string::npos);
  EXPECT_NE(html.find("<td>material_moved_kg</td><td>800</td><td>0.05</td><td>40</td>"), std::string::npos) << html;
  EXPECT_EQ(count(html, "<img src=\"frames/frame_"), 8u);
  EXPECT_NE(html.find("frames/frame_000000.png"), std::string::npos);
  EXPECT_NE(html.find("frames/frame_000099.png"), std::string::npos);
  report["recording"] = nullptr;  // no recording: no strip
  EXPECT_EQ(count(render_report_html(report), "<img"), 0u);
}

}  // namespace
}  // namespace skidsim::report
