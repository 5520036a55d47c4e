// A session's report (the report.json `skidsim run` writes) as one HTML page
// a trainer can open anywhere: no scripts; nothing outside it but the
// recorded frames beside it, when there are some.
#pragma once

#include <nlohmann/json_fwd.hpp>

#include <string>

namespace skidsim::report {

// The session's report as one HTML page (no scripts; only the strip of
// frames is read from beside it): the exercise's name, a pass/fail banner with the score
// against the pass score, the end reason, mode and operator; tables of the
// tasks, metrics (and those not measured yet), events, control-input counts
// and performance; the score term by term; a strip of up to 8 recorded
// frames (frames/ beside the page); the final state hash; one inline-SVG line plot per
// series of report["timeline"] (columnar: "t_s" and equal-length numeric
// arrays, at most 600 points drawn per plot, events of severity >= 1 as
// vertical lines). All text from the report is HTML-escaped. Never throws on
// missing or mistyped keys: what is absent is left out, a series that is not
// all finite numbers or not as long as "t_s" is skipped.
std::string render_report_html(const nlohmann::json& report);

}  // namespace skidsim::report
