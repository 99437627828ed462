#!/usr/bin/env python3
"""Writes docs/accuracy.md (to stdout) from the results scripts/measure.sh collected in WORK_DIR.

Usage: accuracy_tables.py WORK_DIR MODELS_DIR MODELS_NAMED
"""
import json
import os
import statistics
import sys

work, models_dir, models_named = sys.argv[1], sys.argv[2], sys.argv[3]


def load(name):
    with open(os.path.join(work, name + ".json")) as f:
        return json.load(f)


def command(name):
    """The arguments as a user would type them: the models' folder and the kinds' file by name."""
    with open(os.path.join(work, name + ".command")) as f:
        return f.read().strip().replace(os.path.join(work, "kinds.json"), "KINDS.json").replace(models_dir, "MODELS")


def pct(rate):
    return f"{100 * rate:.1f} %"


def interval(share):
    low, high = share["rate_interval_95"]
    return f"{100 * low:.1f}-{100 * high:.1f}"


def share(successes, trials):
    return f"{successes}/{trials}"


def mm(metres):
    return "-" if metres is None else f"{1000 * metres:.1f} mm"


def sessions_by_family(result):
    by_family = {}
    for s in result["sessions"]:
        by_family.setdefault(s["family"], []).append(s)
    return by_family


def sessions_table(name):
    result = load(name)
    by_family = sessions_by_family(result)
    lines = [
        "| kind | sessions | tooltip within 10 mm (95 % interval) | median error | with the true frame "
        "| relative to the true model aligned on the merge (95 % interval) "
        "| confident | confident: tooltip within 15 mm (95 % interval) |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for row in result["summary"]:
        cases = result["sessions"] if row["family"] == "all" else by_family[row["family"]]
        errors = [s["tooltip_error_m"] for s in cases if s["tooltip_error_m"] is not None]
        confident, relative = row["confident_tooltip_within_15mm"], row["tooltip_within_tolerance_relative"]
        confident_text = f"{pct(confident['rate'])} ({interval(confident)})" if confident["trials"] else "-"
        kind = f"**{row['family']}**" if row["family"] == "all" else row["family"]
        lines.append(
            f"| {kind} | {row['sessions']} | {share(row['tooltip_within_tolerance'], row['sessions'])} "
            f"{pct(row['rate'])} ({interval(row)}) | {mm(statistics.median(errors)) if errors else '-'} "
            f"| {share(row['tooltip_within_tolerance_true_frame'], row['sessions'])} "
            f"| {share(relative['successes'], relative['trials'])} {pct(relative['rate'])} ({interval(relative)}) "
            f"| {row['confident']} | {confident_text} |")
    return "\n".join(lines)


def worst_sessions(name, count=3):
    """The worst sessions of each kind: what still fails."""
    result = load(name)
    by_family = sessions_by_family(result)
    lines = []
    for family, cases in by_family.items():
        misses = [s for s in cases if s["tooltip_error_m"] is None or s["tooltip_error_m"] > 0.010]
        misses.sort(key=lambda s: -(s["tooltip_error_m"] if s["tooltip_error_m"] is not None else 1e9))
        if not misses:
            continue
        described = []
        for s in misses[:count]:
            what = os.path.basename(s["model"]) + " " if s["model"] else ""
            if s["failure"]:
                described.append(f"{what}seed {s['seed']}: failed ({s['failure']})")
                continue
            frame = []
            if s["handle_axis_error_deg"] is not None and s["handle_axis_error_deg"] > 3:
                frame.append(f"handle {s['handle_axis_error_deg']:.0f} deg off")
            if s["symmetry_plane_error_deg"] is not None and s["symmetry_plane_error_deg"] > 10:
                frame.append(f"plane {s['symmetry_plane_error_deg']:.0f} deg off")
            if s["effector_sign_right"] is False:
                frame.append("effector reversed")
            described.append(
                f"{what}seed {s['seed']}: {mm(s['tooltip_error_m'])} ({', '.join(frame) or 'frame right'}; "
                f"{mm(s['tooltip_error_true_frame_m'])} with the true frame; "
                f"{'confident' if s['confident'] else 'doubtful'})")
        lines.append(f"- {family}, {len(misses)} of {len(cases)} beyond 10 mm; the worst: " + "; ".join(described))
    return "\n".join(lines) if lines else "- none beyond 10 mm"


def shipped_threshold():
    """The probability from which the shipped frame score calls a result confident."""
    with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "configs", "frame-score.json")) as f:
        return json.load(f)["confident_probability"]


def probability_table(names):
    """The chosen tooltip's probability against how often it is right (within 15 mm; the sessions' relative
    error), per set, in evaluate-models' bins: the confidence's calibration on the exam."""
    model_bins = load("models")["all"]["probability_bins"]
    bins = [tuple(b["probability"]) for b in model_bins]

    def cell(right, cases):
        return f"{right}/{cases}" + (f" ({pct(right / cases)})" if cases else "")

    lines = ["| set | " + " | ".join(f"{lo:.2f}-{hi:.2f}" for lo, hi in bins) + " |", "|---|" + "---|" * len(bins)]
    for name, label in names:
        cases = [s for s in load(name)["sessions"] if s["tooltip_error_relative_m"] is not None]
        cells = []
        for lo, hi in bins:
            inside = [s for s in cases if lo <= s["tooltip_probability"] < hi or s["tooltip_probability"] == hi == 1.0]
            cells.append(cell(sum(s["tooltip_error_relative_m"] <= 0.015 for s in inside), len(inside)))
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    lines.append("| models held | " + " | ".join(cell(b["tooltip_within_15mm"], b["cases"]) for b in model_bins) + " |")
    return "\n".join(lines)


def models_table():
    result = load("models")
    lines = [
        "| kind | cases | tooltip within 10 mm (95 % interval) | handle axis within 3 deg (95 % interval) "
        "| median error | right-handed | effector sign right (salient) | confident: tooltip within 15 mm |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for row in result["kinds"] + [result["all"]]:
        tip, handle, confident = (row["tooltip_within_10mm"], row["handle_axis_within_3deg"],
                                  row["confident_tooltip_within_15mm"])
        kind = f"**{row['kind']}**" if row["kind"] == "all" else row["kind"]
        confident_text = (f"{share(confident['successes'], confident['trials'])} {pct(confident['rate'])} "
                          f"({interval(confident)})" if confident["trials"] else "none confident")
        lines.append(
            f"| {kind} | {row['cases']} | {share(tip['successes'], tip['trials'])} {pct(tip['rate'])} "
            f"({interval(tip)}) | {pct(handle['rate'])} ({interval(handle)}) | {mm(row['median_tooltip_m'])} "
            f"| {row['cases'] - row['left_handed']}/{row['cases']} "
            f"| {share(row['effector_sign_right'], row['salient_cases']) if row['salient_cases'] else '-'} "
            f"| {confident_text} |")
    worst = sorted(result["models"], key=lambda m: m["tooltip_within_10mm"]["rate"])[:8]
    below = [m for m in worst if m["tooltip_within_10mm"]["rate"] < 0.9]
    tail = ", ".join(f"{os.path.basename(m['model'])} {pct(m['tooltip_within_10mm']['rate'])} "
                     f"(median {mm(m['median_tooltip_m'])})" for m in below)
    return "\n".join(lines), tail or "none"


def poses_table():
    result = load("poses")
    lines = [
        "| kind | cases | right (95 % interval) | pose right | tooltip right | median translation | median tooltip error |",
        "|---|---|---|---|---|---|---|",
    ]
    for row in result["kinds"] + [result["all"]]:
        kind = f"**{row['kind']}**" if row["kind"] == "all" else row["kind"]
        lines.append(
            f"| {kind} | {row['cases']} | {share(row['right'], row['cases'])} {pct(row['rate'])} ({interval(row)}) "
            f"| {row['pose_right']} | {row['tooltip_right']} | {mm(row['median_translation_m'])} "
            f"| {mm(row['median_tooltip_m'])} |")
    wrong = [c for c in result["cases"] if not c["right"]]
    described = "; ".join(
        f"{os.path.basename(c['model'])} grasp {c['grasp']}: "
        + (f"failed ({c['failure']})" if c["failure"] else
           f"{c['rotation_deg']:.0f} deg, {mm(c['translation_m'])}, tooltip {mm(c['tooltip_m'])}"
           f"{', ambiguous' if c['ambiguous'] else ''}{'' if c['feasible'] else ', infeasible'}")
        for c in wrong)
    return "\n".join(lines), described or "none"


def bench_table(name, what):
    path = os.path.join(work, name + ".json")
    if not os.path.exists(path):
        return f"{what}: not measured (the benchmarks were not built: TOOLINC_BUILD_BENCHMARKS)."
    with open(path) as f:
        runs = json.load(f)["benchmarks"]
    lines = [f"| {what} | CPU time per call |", "|---|---|"]
    for run in runs:
        label = f"{run['name']}: {run['label']}" if run.get("label") else run["name"]
        lines.append(f"| {label} | {run['cpu_time']:.1f} {run['time_unit']} |")
    return "\n".join(lines)


def peers_output():
    path = os.path.join(work, "bench_peers.txt")
    if not os.path.exists(path):
        return "Not measured: bench_peers was not built (TOOLINC_BUILD_BENCHMARKS)."
    with open(path) as f:
        return "```\n" + f.read().strip() + "\n```"


models, worst_models = models_table()
poses, wrong_poses = poses_table()
print(f"""# Accuracy and speed, measured

Generated by `scripts/measure.sh` (every figure below comes from its run; rerun it after a change to the
method, and commit the result). Rates are tooltips within 10 mm of the ground truth, with 95 % Wilson
intervals; "with the true frame" applies the tooltip rule with the true tool frame, so the gap between the
two columns is the frame's share of the misses; "confident" counts the results the method calls
confident, and the last column how many of those are within 15 mm. The ground truth is the paper's
weighted rule, except a flat or scooped blade continuing the handle (a shovel), whose tip is the blade's
far end. How the method works and why it fails where it does: [method.md](method.md); the simulator:
[simulation.md](simulation.md).

(Part of [toolinc](../README.md).)

## Generated families, robot-like stereo

The default sessions: each family's tool held with a recorded grasp, seen from the five exploration poses
through the simulated LIBELAS-like stereo (smear at depth edges, interpolated gaps), cropped, merged, and
the frame and tooltip estimated on the merged cloud (`build/bin/evaluate-sessions {command('elas')}`).

{sessions_table('elas')}

What still fails:
{worst_sessions('elas')}

## Generated families, merged as the robot's reconstructions were

The same sessions with the views merged as the original exploreTool made the robot's reconstructions: at
their recorded poses, without registration or the smear check, kept as bare points
(`build/bin/evaluate-sessions {command('original')}`; [simulation.md](simulation.md#the-robots-reconstructions-the-originals-merge-evaluate-sessions---reconstruction-original)).
Their fringe comes half way to the robot's, and they are the generated exam nearest its clouds.

{sessions_table('original')}

What still fails:
{worst_sessions('original')}

## Generated families, ideal stereo

The same sessions with exact disparity (`build/bin/evaluate-sessions {command('ideal')}`): the method's
own error, without the stereo's.

{sessions_table('ideal')}

With any grasp (the effector facing any way, `build/bin/evaluate-sessions {command('ideal_any')}`):

{sessions_table('ideal_any')}

What still fails there:
{worst_sessions('ideal_any')}

## Models under random grasps

{models_named[0].upper() + models_named[1:]}, each held with random grasps (rotation about the handle +/-90 degrees, tilt +/-45, roll
+/-15, offsets +/-5 cm), the points within 6 cm of the hand removed, Gaussian noise of sigma 1.5 mm; the
ground truth modulo the model's measured symmetry (`build/bin/evaluate-models MODELS {command('models')}`).

{models}

Models below 90 %: {worst_models}.

## Sessions of the models, robot-like stereo

The same models through the default sessions (`build/bin/evaluate-sessions {command('model_sessions')}`).

{sessions_table('model_sessions')}

What still fails:
{worst_sessions('model_sessions')}

## The confidence against how often it is right

The frame search's probability of the chosen tooltip (each session's `tooltip_probability` in
evaluate-sessions' output, evaluate-models' `probability_bins`), binned, against how many of those
tooltips lie within 15 mm of the truth (for a session, carried by the true model aligned onto the merge):
right/cases (share). `configs/frame-score.json`
calls a result confident from probability {shipped_threshold():.3f}, set on simulated sessions of the
generated families never fitted on (their calibration table is in that file), where its other checks pass.

{probability_table([("elas", "families' sessions"), ("original", "families merged as the robot's"),
                    ("model_sessions", "models' sessions")])}

## align-pose on the models

A known tool's pose in the hand from one partial view: {models_named}, each held with random grasps (any
turn about the handle, tilt +/-60 degrees, roll +/-15, offsets +/-5 cm), one rendered partial view per
grasp (back faces and what the hand hides gone, the points within 6 cm of the hand cropped, sigma 1.5
mm); right = rotation within 3 degrees and translation within 5 mm, or tooltip within 10 mm, modulo the
model's measured symmetry ("pose" and "tooltip" count each alone; `build/bin/evaluate-poses MODELS
{command('poses')}`).

{poses}

Wrong: {wrong_poses}.

## Speed

The benchmarks (`build/bench/`, Google Benchmark) on one core (`taskset -c 0`), CPU time per call (wall
time on a loaded machine is larger). `bench_tool_frame`: estimate-frame + find-tooltip on a held
generated tool of about 10k points.

{bench_table("bench_tool_frame", "estimate-frame + find-tooltip")}

`bench_session_pipeline`: crop-cloud on one view, merge-views of five, and the whole offline pipeline of
a five-view session (0 ideal, 1 SGBM, 2 LIBELAS-like stereo).

{bench_table("bench_session_pipeline", "session pipeline")}

`bench_align_pose`: align-pose of a generated model onto a partial view, per family.

{bench_table("bench_align_pose", "align-pose")}

### Against the peers

`bench_peers`: each building block beside the same block of nanoflann, PCL and Open3D where they are
installed (`apt-get install libnanoflann-dev libopen3d-dev`; benchmark-only, never needed by the library),
in one process, on the same clouds, on one core: median wall time, its ratio to the fastest peer, and what
the block produced, so that times compare at equal results. toolinc has no point-to-point ICP; its
point-to-plane row stands beside the peers' point-to-point. No peer does align-pose's whole job (a view
onto its model from no initial guess), so its baseline is the composition the peers' tutorials give: FPFH
features on a 5 mm grid, a RANSAC over feature matches (Open3D's `RegistrationRANSACBasedOnFeatureMatching`
with its edge-length and distance checkers, PCL's `SampleConsensusPrerejective`), then point-to-plane ICP;
on the same random grasps of the families, timed with the model's preparation, and counted right within 3
degrees, 5 mm and a tooltip within 10 mm. Nor does any peer merge a session's views: its baseline is each
view registered onto the first by point-to-plane ICP from its recorded pose, the views concatenated,
resampled on a 2 mm grid and cleaned by the statistical outlier filter; the merged models' distance from
the true surface beside the times. No peer estimates a tool's frame: frame + tooltip has no row. Then the scaling of the whole jobs from 3k to 1M points (the
same surfaces sampled more densely), with the exponent of a power law fitted from 10k up.

{peers_output()}
""", end="")
