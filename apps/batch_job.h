// `skidsim batch LIST`: many sessions at once on this machine, each a
// `skidsim run` of its own (a process: sessions share nothing), at most
// --jobs at a time, each into its own run directory under --out; then a
// summary (batch.json and a table). With --index K only entry K runs: one
// task of a cluster's array job (docs/batch.md).
//
// LIST: one session per line, the arguments of `skidsim run` (an exercise
// and its options, whitespace-separated, paths as from the current folder);
// '#' starts a comment. Each entry needs --script or --replay: a batch has
// no people at the controls. --out and --lcm are the batch's to set.
#pragma once

#include <string>

namespace skidsim::apps {

struct BatchJob {
  std::string list_path;
  std::string out_dir = "runs/batch";
  int jobs = 0;     // 0: the machine's cores
  int index = 0;    // 1-based entry to run alone; 0: all
};

// 0 when every session ran (each report.json says whether it passed), 1
// when one failed, 2 for a bad list (file and line named, nothing run).
int run_batch(const BatchJob& job);

}  // namespace skidsim::apps
