#!/usr/bin/env python3
"""Summarise a run of the reliability suite into a Markdown report.

    SKIDSIM_RELIABILITY_RESULTS=/tmp/rel ctest --test-dir build -L reliability -j2
    scripts/reliability_report.py /tmp/rel > RELIABILITY_FAILURES.md

Each case wrote one JSON file (tests/reliability_test.cpp): what it did to
its input, the command, what the binary did, and which checks failed. The
report lists every failing case, grouped by format and mutation family.
"""
import collections
import glob
import json
import os
import sys


def behaviour(j):
    if j["timed_out"]:
        return "hang (killed after the limit)"
    if j["signal"]:
        return "killed by " + j["signal"]
    return "exit %d" % j["exit_code"]


def cell(text, n=160):
    text = " ".join(str(text).split())
    if len(text) > n:
        text = text[:n] + "..."
    return text.replace("|", "\\|")


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    cases = [json.load(open(p)) for p in sorted(glob.glob(os.path.join(sys.argv[1], "*.json")))]
    total = collections.Counter(c["format"] for c in cases)
    failing = [c for c in cases if c["failures"]]
    failed = collections.Counter(c["format"] for c in failing)
    groups = collections.defaultdict(list)
    for c in failing:
        groups[(c["format"], c["family"])].append(c)

    out = []
    out.append("# Reliability suite: failing cases\n")
    out.append("%d cases ran, %d failed. Re-run one with "
               "`SKIDSIM_RELIABILITY_KEEP=1 ctest --test-dir build -R 'NAME$' --output-on-failure` "
               "(the case's folder is kept; the command below names it).\n" % (len(cases), len(failing)))
    out.append("| format | cases | failing |\n|---|---|---|")
    for f in sorted(total):
        out.append("| %s | %d | %d |" % (f, total[f], failed[f]))
    out.append("")
    out.append("## Families\n")
    out.append("| format / family | failing | what fails (first check of the first case) |\n|---|---|---|")
    for (f, fam), cs in sorted(groups.items()):
        out.append("| %s / %s | %d | %s |" % (f, fam, len(cs), cell(cs[0]["failures"][0], 120)))
    out.append("")
    for (f, fam), cs in sorted(groups.items()):
        out.append("## %s / %s (%d failing)\n" % (f, fam, len(cs)))
        kinds = collections.Counter(c["failures"][0].split(":")[0][:60] for c in cs)
        out.append("Checks that failed: " + "; ".join("%s (%d)" % (k, n) for k, n in kinds.most_common()) + "\n")
        out.append("Example: `%s` (%s)\n" % (cs[0]["command"], cs[0]["what"]))
        out.append("| case | mutation | binary | failed checks | stderr |\n|---|---|---|---|---|")
        for c in cs:
            out.append("| %s | %s | %s | %s | %s |" % (
                c["name"], cell(c.get("what", ""), 90), behaviour(c),
                cell("; ".join(c["failures"]), 140), cell(c["stderr"], 160) or "(empty)"))
        out.append("")
    print("\n".join(out))


if __name__ == "__main__":
    main()
