#!/usr/bin/env python3
"""The state of a batch run over sessions, shared by scripts/pipeline.mk and scripts/Snakefile.

usage: scripts/session_summary.py SESSIONS OUT

Every session (a folder of SESSIONS with session.json) is done, failed (the first failed step and its
error) or not run. Writes OUT/summary.csv (one row per session, failed ones included) and prints the table
on stderr. Exit 0 when every session is done, 3 when some is not, 2 on bad usage or no session.

Both workflows write each step's stderr to OUT/NAME/logs/STEP.log and remove a step's output before the
step runs, so a step failed when its log says something and its output is missing; a session is done when
its report exists and no step of it failed (a report left from an earlier run is not a success).
"""
import csv
import glob
import json
import os
import sys

# Each session's steps in order, with the output that exists only when the step succeeded.
STEPS = [("crop_cloud", "views"), ("merge_views", "model.ply"), ("estimate_frame", "frame.json"),
         ("find_tooltip", "tooltip.json"), ("evaluate", "evaluation.json"), ("render_model", "model.png"),
         ("render_sheet", "sheet.png"), ("report", "report.html")]
STEP_NAMES = [step for step, _ in STEPS]

COLUMNS = ["session", "status", "views", "views_accepted", "tooltip_x", "tooltip_y", "tooltip_z",
           "tooltip_error_mm", "handle_axis_error_deg", "effector_axis_error_deg", "origin_error_mm", "failure"]


def session_names(sessions):
    return sorted(os.path.basename(os.path.dirname(path))
                  for path in glob.glob(os.path.join(glob.escape(sessions), "*", "session.json")))


def has_truth(sessions, name):
    return os.path.exists(os.path.join(sessions, name, "ground_truth.json"))


def step_error(out, name, step):
    """The last line the step wrote to its log (its error), or "" when it wrote nothing."""
    log = os.path.join(out, name, "logs", step + ".log")
    if not os.path.exists(log):
        return ""
    with open(log, errors="replace") as f:
        lines = [line.strip() for line in f if line.strip()]
    return lines[-1] if lines else ""


def session_status(out, name):
    """("done", ""), ("failed", "STEP: its error") or ("not run", "")."""
    folder = os.path.join(out, name)
    for step, output in STEPS:
        error = step_error(out, name, step)
        if error and not os.path.exists(os.path.join(folder, output)):
            return "failed", f"{step}: {error}"
    if os.path.exists(os.path.join(folder, "report.html")):
        return "done", ""
    return "not run", ""


def summary_row(sessions, out, name):
    status, failure = session_status(out, name)
    row = {"session": name, "status": status, "failure": failure}
    if status != "done":
        return row
    folder = os.path.join(out, name)
    with open(os.path.join(folder, "merge_report.json")) as f:
        views = json.load(f)["views"]
    with open(os.path.join(folder, "tooltip.json")) as f:
        tip = json.load(f)["position"]
    row.update({"views": len(views), "views_accepted": sum(v["accepted"] for v in views),
                "tooltip_x": f"{tip[0]:.6f}", "tooltip_y": f"{tip[1]:.6f}", "tooltip_z": f"{tip[2]:.6f}"})
    if has_truth(sessions, name):
        with open(os.path.join(folder, "evaluation.json")) as f:
            errors = json.load(f)
        row["tooltip_error_mm"] = f"{1000 * errors['tooltip']['error_m']:.3f}"
        row["handle_axis_error_deg"] = f"{errors['frame']['handle_axis_error_deg']:.3f}"
        row["effector_axis_error_deg"] = f"{errors['frame']['effector_axis_error_deg']:.3f}"
        row["origin_error_mm"] = f"{1000 * errors['frame']['origin_error_m']:.3f}"
    return row


def write_summary(sessions, out, names):
    """Writes OUT/summary.csv (through a temporary file) and returns its rows."""
    rows = [summary_row(sessions, out, name) for name in names]
    os.makedirs(out, exist_ok=True)
    target = os.path.join(out, "summary.csv")
    temporary = target + ".tmp"
    with open(temporary, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=COLUMNS, restval="", lineterminator="\n")
        writer.writeheader()
        writer.writerows(rows)
    os.replace(temporary, target)
    return rows


def print_table(rows, file=sys.stderr):
    width = max(len(row["session"]) for row in rows + [{"session": "session"}])
    print(f"toolinc: {'session':<{width}}  status   reason", file=file)
    for row in rows:
        print(f"toolinc: {row['session']:<{width}}  {row['status']:<7}  {row['failure']}".rstrip(), file=file)
    counts = {s: sum(row["status"] == s for row in rows) for s in ("done", "failed", "not run")}
    print(f"toolinc: {counts['done']} done, {counts['failed']} failed, {counts['not run']} not run, of {len(rows)}; "
          "the same command again redoes only what is missing", file=file, flush=True)


def main(argv):
    if len(argv) != 3:
        print("usage: session_summary.py SESSIONS OUT", file=sys.stderr)
        return 2
    sessions, out = argv[1], argv[2]
    names = session_names(sessions)
    if not names:
        print(f"toolinc: no session (a folder with session.json) under {sessions}", file=sys.stderr)
        return 2
    rows = write_summary(sessions, out, names)
    print_table(rows)
    print(f"toolinc: summary in {os.path.join(out, 'summary.csv')}", file=sys.stderr)
    return 0 if all(row["status"] == "done" for row in rows) else 3


if __name__ == "__main__":
    sys.exit(main(sys.argv))
