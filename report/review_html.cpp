#include "report/review_html.h"

#include <algorithm>
#include <cmath>
#include <nlohmann/json.hpp>

namespace skidsim::report {
namespace {

using nlohmann::json;

// The report is read, not trusted: absent or mistyped keys give null.
const json& field(const json& j, const char* key) {
  static const json null_value;
  if (!j.is_object()) return null_value;
  const auto it = j.find(key);
  return it == j.end() ? null_value : *it;
}

double number_or(const json& j, double fallback) {
  return j.is_number() && std::isfinite(j.get<double>()) ? j.get<double>() : fallback;
}

std::string text_or(const json& j, const std::string& fallback) { return j.is_string() ? j.get<std::string>() : fallback; }

// The series of the timeline that are all finite numbers, as long as t_s.
json clean_timeline(const json& timeline) {
  json out = json::object();
  const json& t = field(timeline, "t_s");
  if (!t.is_array() || t.empty()) return out;
  for (const auto& [name, series] : timeline.items()) {
    if (!series.is_array() || series.size() != t.size()) continue;
    bool finite = true;
    for (const json& v : series) finite = finite && v.is_number() && std::isfinite(v.get<double>());
    if (finite) out[name] = series;
  }
  if (!out.contains("t_s")) return json::object();
  return out;
}

// The page's script: everything is drawn from DATA on load.
const char* const kScript = R"JS(
"use strict";
const DATA = JSON.parse(document.getElementById("data").textContent);
const $ = (id) => document.getElementById(id);
window.addEventListener("error", (e) => {
  const li = document.createElement("li");
  li.textContent = String(e.message);
  $("errors").appendChild(li);
});
const SVG = "http://www.w3.org/2000/svg";
const W = 560, H = 110, LEFT = 56, RIGHT = 8, TOP = 6, BOTTOM = 18;
const t_end = DATA.duration_s > 0 ? DATA.duration_s : 1;
let frame_set = DATA.frame_sets.length ? DATA.frame_sets[0] : null;
let playing = null;

function x_of(t) { return LEFT + (W - LEFT - RIGHT) * Math.min(Math.max(t / t_end, 0), 1); }
function svg_el(name, attrs, parent) {
  const e = document.createElementNS(SVG, name);
  for (const k in attrs) e.setAttribute(k, attrs[k]);
  if (parent) parent.appendChild(e);
  return e;
}

// One plot per timeline series, a marker line in each.
function draw_plots() {
  const t = DATA.timeline.t_s || [];
  for (const name of Object.keys(DATA.timeline)) {
    if (name === "t_s") continue;
    const v = DATA.timeline[name];
    let lo = Infinity, hi = -Infinity;
    for (const y of v) { lo = Math.min(lo, y); hi = Math.max(hi, y); }
    if (!(hi > lo)) { hi = lo + 1; }
    const box = document.createElement("div");
    box.className = "plot";
    const title = document.createElement("div");
    title.textContent = name.replace(/_/g, " ");
    box.appendChild(title);
    const svg = svg_el("svg", {width: W, height: H, "data-series": name}, box);
    svg_el("rect", {x: LEFT, y: TOP, width: W - LEFT - RIGHT, height: H - TOP - BOTTOM, class: "frame"}, svg);
    const y_of = (y) => TOP + (H - TOP - BOTTOM) * (1 - (y - lo) / (hi - lo));
    const step = Math.max(1, Math.floor(t.length / 600));
    let points = "";
    for (let k = 0; k < t.length; k += step) points += x_of(t[k]).toFixed(1) + "," + y_of(v[k]).toFixed(1) + " ";
    svg_el("polyline", {points: points, class: "series"}, svg);
    for (const [y, anchor] of [[hi, TOP + 8], [lo, H - BOTTOM]]) {
      const label = svg_el("text", {x: LEFT - 4, y: anchor, "text-anchor": "end"}, svg);
      label.textContent = Number(y.toPrecision(4)).toString();
    }
    const end = svg_el("text", {x: W - RIGHT, y: H - 4, "text-anchor": "end"}, svg);
    end.textContent = t_end.toFixed(1) + " s";
    for (const e of DATA.events)
      if (e.severity >= 1) svg_el("line", {x1: x_of(e.time_s), x2: x_of(e.time_s), y1: TOP, y2: H - BOTTOM, class: "event"}, svg);
    svg_el("line", {x1: LEFT, x2: LEFT, y1: TOP, y2: H - BOTTOM, class: "marker"}, svg);
    svg.addEventListener("click", (ev) => {
      const r = svg.getBoundingClientRect();
      seek((ev.clientX - r.left - LEFT) / (W - LEFT - RIGHT) * t_end);
    });
    $("plots").appendChild(box);
  }
}

function draw_events() {
  const body = $("events");
  DATA.events.forEach((e, k) => {
    const tr = document.createElement("tr");
    tr.dataset.t = e.time_s;
    tr.className = "sev" + e.severity;
    for (const c of [e.time_s.toFixed(2), e.kind, e.text]) {
      const td = document.createElement("td");
      td.textContent = c;
      tr.appendChild(td);
    }
    tr.addEventListener("click", () => seek(e.time_s));
    body.appendChild(tr);
  });
}

function draw_score() {
  const body = $("score");
  for (const b of DATA.breakdown) {
    const tr = document.createElement("tr");
    for (const c of [b.metric, Number(b.value.toPrecision(6)), b.weight, b.points.toFixed(2)]) {
      const td = document.createElement("td");
      td.textContent = c;
      tr.appendChild(td);
    }
    body.appendChild(tr);
  }
}

// The one place the time is shown: scrubber, frame, markers, events.
function show(t) {
  t = Math.min(Math.max(t, 0), t_end);
  document.body.dataset.time = t.toFixed(3);
  $("time").textContent = t.toFixed(2) + " s";
  if (frame_set && frame_set.frames > 0) {
    const k = Math.min(frame_set.frames - 1, Math.floor(t * frame_set.fps + 1e-6));
    const name = "frame_" + String(k).padStart(6, "0") + ".png";
    const src = frame_set.dir + "/" + name;
    // A frame the set lacks is said to be missing, not left as a broken image.
    const gone = (frame_set.missing || []).some((r) => k >= r[0] && k <= r[1]);
    if (gone) {
      $("frame").removeAttribute("src");
      $("frame").alt = name + " is missing";
    } else if ($("frame").getAttribute("src") !== src) {
      $("frame").setAttribute("src", src);
      $("frame").alt = "recorded frame";
    }
    $("frame_note").textContent = gone ? frame_set.dir + "/" + name + " is missing" : "";
    document.body.dataset.frame = k;
  }
  const x = x_of(t).toFixed(1);
  for (const m of document.querySelectorAll("line.marker")) { m.setAttribute("x1", x); m.setAttribute("x2", x); }
  let current = null;
  for (const tr of $("events").children) {
    tr.classList.toggle("past", Number(tr.dataset.t) <= t + 1e-9);
    tr.classList.remove("current");
    if (Number(tr.dataset.t) <= t + 1e-9) current = tr;
  }
  if (current) current.classList.add("current");
}

function seek(t) {
  const s = $("scrub");
  s.value = t;
  s.dispatchEvent(new Event("input"));
}

// Playing keeps its own clock: the scrubber's value snaps to its step.
function play() {
  if (playing) { clearInterval(playing); playing = null; $("play").textContent = "play"; return; }
  $("play").textContent = "pause";
  let last = performance.now(), t = Number($("scrub").value);
  if (t >= t_end) t = 0;
  playing = setInterval(() => {
    const now = performance.now();
    t = Math.min(t + (now - last) / 1000 * Number($("speed").value), t_end);
    last = now;
    $("scrub").value = t;
    show(t);
    if (t >= t_end) play();
  }, 50);
}

function from_address() {
  const m = /t=([0-9.]+)/.exec(location.hash);
  if (m) seek(Number(m[1]));
}

function start() {
  $("title").textContent = DATA.name;
  $("verdict").textContent = (DATA.passed ? "PASSED" : "NOT PASSED") + ": score " + DATA.score.toFixed(2) +
      " (pass " + DATA.pass_score + "), ended by " + DATA.end_reason;
  $("verdict").className = DATA.passed ? "pass" : "fail";
  const s = $("scrub");
  s.max = t_end;
  s.step = "any";
  s.addEventListener("input", () => show(Number(s.value)));
  const pick = $("camera");
  DATA.frame_sets.forEach((f, k) => {
    const o = document.createElement("option");
    o.value = k;
    o.textContent = f.label;
    pick.appendChild(o);
  });
  pick.addEventListener("change", () => { frame_set = DATA.frame_sets[Number(pick.value)]; show(Number(s.value)); });
  for (const f of DATA.frame_sets) {  // every set's missing frames, said once at the top
    if (!f.missing.length) continue;
    const li = document.createElement("li");
    const n = f.missing.reduce((sum, r) => sum + r[1] - r[0] + 1, 0);
    li.textContent = f.dir + "/: " + n + " of " + f.frames + " frames missing (" +
        f.missing.map((r) => r[0] === r[1] ? String(r[0]) : r[0] + "-" + r[1]).join(", ") + ")";
    $("missing").appendChild(li);
  }
  if (!frame_set) $("frame").replaceWith(Object.assign(document.createElement("p"), {textContent: "No frames were recorded (skidsim run --record)."}));
  $("play").addEventListener("click", play);
  document.addEventListener("keydown", (e) => {
    const dt = frame_set ? 1 / frame_set.fps : 0.1;
    if (e.key === "ArrowRight") seek(Number(s.value) + dt);
    if (e.key === "ArrowLeft") seek(Number(s.value) - dt);
  });
  draw_plots();
  draw_events();
  draw_score();
  show(0);
  from_address();
  window.addEventListener("hashchange", from_address);
}
start();
)JS";

const char* const kStyle = R"CSS(
body { font-family: sans-serif; margin: 16px; color: #222; }
.pass { color: #176a1f; font-weight: bold; } .fail { color: #a11; font-weight: bold; }
#viewer { display: flex; gap: 16px; flex-wrap: wrap; align-items: flex-start; }
#frame { max-width: 100%; width: 640px; background: #ccc; }
#controls { margin: 8px 0; display: flex; gap: 8px; align-items: center; }
#scrub { width: 520px; }
.plot svg { display: block; } .plot { margin-bottom: 6px; font-size: 12px; }
rect.frame { fill: #fafafa; stroke: #bbb; } polyline.series { fill: none; stroke: #1f5fa8; stroke-width: 1.3; }
line.marker { stroke: #d11; stroke-width: 1.5; } line.event { stroke: #e90; stroke-dasharray: 3 2; }
svg text { font-size: 10px; fill: #555; }
table { border-collapse: collapse; font-size: 13px; } td, th { border: 1px solid #ddd; padding: 2px 6px; text-align: left; }
#events tr { cursor: pointer; color: #888; } #events tr.past { color: #222; } #events tr.current { background: #fde9a9; }
#events tr.sev1 td:nth-child(2) { color: #b60; } #events tr.sev2 td:nth-child(2) { color: #c00; font-weight: bold; }
#errors { color: #c00; } .warn { color: #b60; }
)CSS";

}  // namespace

std::string render_review_html(const json& report, const std::vector<FrameSet>& frame_sets) {
  const json& result = field(report, "result");
  json data;
  data["name"] = text_or(field(field(report, "exercise"), "name"), "session");
  data["passed"] = field(result, "passed").is_boolean() && field(result, "passed").get<bool>();
  data["score"] = number_or(field(result, "score"), 0.0);
  data["pass_score"] = number_or(field(result, "pass_score"), 0.0);
  data["end_reason"] = text_or(field(report, "end_reason"), "unknown");
  data["timeline"] = clean_timeline(field(report, "timeline"));
  data["events"] = json::array();
  double duration_s = 0.0;
  if (data["timeline"].contains("t_s")) duration_s = data["timeline"]["t_s"].back().get<double>();
  if (field(report, "events").is_array())
    for (const json& e : field(report, "events")) {
      const double t = number_or(field(e, "time_s"), -1.0);
      if (t < 0.0) continue;
      duration_s = std::max(duration_s, t);
      data["events"].push_back({{"time_s", t}, {"kind", text_or(field(e, "kind"), "")},
                                {"severity", static_cast<int>(std::clamp(number_or(field(e, "severity"), 0.0), 0.0, 2.0))},
                                {"text", text_or(field(e, "text"), "")}});
    }
  data["duration_s"] = duration_s;
  data["breakdown"] = json::array();
  if (field(result, "score_breakdown").is_array())
    for (const json& b : field(result, "score_breakdown"))
      data["breakdown"].push_back({{"metric", text_or(field(b, "metric"), "?")},
                                   {"value", number_or(field(b, "value"), 0.0)},
                                   {"weight", number_or(field(b, "weight"), 0.0)},
                                   {"points", number_or(field(b, "points"), 0.0)}});
  data["frame_sets"] = json::array();
  for (const FrameSet& f : frame_sets)
    if (f.frames > 0 && f.fps > 0.0)
    {
      json missing = json::array();
      for (const auto& [first, last] : f.missing) missing.push_back({first, last});
      data["frame_sets"].push_back({{"label", f.label}, {"dir", f.dir}, {"fps", f.fps}, {"frames", f.frames}, {"missing", missing}});
    }
  // No '<' at all inside the script element ("</script>", "<!--" would
  // change how the HTML parser reads it): JSON has it only in strings,
  // where \u003c means the same.
  const std::string dumped = data.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string embedded;
  embedded.reserve(dumped.size());
  for (const char c : dumped) embedded += c == '<' ? std::string("\\u003c") : std::string(1, c);

  std::string html;
  html += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\"><title>skidsim review</title><style>";
  html += kStyle;
  html += "</style></head>\n<body>\n<h1 id=\"title\"></h1>\n<p id=\"verdict\"></p>\n<ul id=\"errors\"></ul>\n";
  html += "<ul id=\"missing\" class=\"warn\"></ul>\n";
  html += "<div id=\"viewer\"><div><img id=\"frame\" alt=\"recorded frame\"><p id=\"frame_note\" class=\"warn\"></p>\n";
  html += "<div id=\"controls\"><button id=\"play\">play</button><input id=\"scrub\" type=\"range\" min=\"0\" value=\"0\">"
          "<span id=\"time\"></span><select id=\"speed\"><option value=\"0.5\">0.5x</option>"
          "<option value=\"1\" selected>1x</option><option value=\"4\">4x</option></select>"
          "<select id=\"camera\"></select></div>\n";
  html += "<h2>Score</h2><table><thead><tr><th>metric</th><th>value</th><th>weight</th><th>points</th></tr></thead>"
          "<tbody id=\"score\"></tbody></table>\n";
  html += "<h2>Events</h2><table><thead><tr><th>t (s)</th><th>kind</th><th>what</th></tr></thead>"
          "<tbody id=\"events\"></tbody></table></div>\n";
  html += "<div id=\"plots\"></div></div>\n";
  html += "<script type=\"application/json\" id=\"data\">" + embedded + "</script>\n<script>";
  html += kScript;
  html += "</script>\n</body></html>\n";
  return html;
}

}  // namespace skidsim::report
