#!/usr/bin/env python3
"""Prints every row of docs/benchmarks.md's table from the JSON files scripts/benchmarks.sh wrote into OUT.

  scripts/benchmark_ratios.py OUT              one line per row: ours, the reference of the same run, the ratio
  scripts/benchmark_ratios.py OUT --markdown   the whole page docs/benchmarks.md
  scripts/benchmark_ratios.py OUT1 OUT2 OUT3 [--markdown]
                                               several runs of scripts/benchmarks.sh: each row with a ratio
                                               from the run of the median ratio, the runs' ratios beside it
                                               (rows without a ratio, and the other tables, from OUT1)
  [OUT ...] --collection [LABEL=]RUN [--collection [LABEL=]RUN2 ...]
                                               also (alone, without OUT) the section "A whole collection": the profile of each
                                               `cshapes experiment retrieval` run folder (its retrieval.json),
                                               e.g. the exact run and a two-stage run of the 400-shape collection
                                               (scripts/make_benchmark400.py)

Exits 1 when an anchor that should have run did not (scikit-learn or Open3D missing:
scripts/install-deps.sh --with-anchors), naming the reason the benchmark gave. Standard library only.
"""
import json
import os
import sys


def load(out, name):
    path = os.path.join(out, name + ".json")
    if not os.path.exists(path):
        return None
    with open(path) as f:
        return json.load(f)


def g(value, digits=3):
    return f"{value:.{digits}g}"


def ratio_text(r):
    return f"{r:.1f}×" if r < 100 else f"{r:.0f}×"


class Row:
    def __init__(self, what, command, ours, reference="—", ratio=None, goal="—", met=None):
        self.what, self.command, self.ours, self.reference = what, command, ours, reference
        self.ratio, self.goal, self.met = ratio, goal, met


def runs_text(row):
    """' (runs: 98.0×, 113×, 100×)' for a row chosen among several runs, else ''."""
    runs = getattr(row, "runs", None)
    return " (runs: " + ", ".join(ratio_text(x) for x in runs) + ")" if runs else ""


def verdict(met):
    return "" if met is None else (" — **met**" if met else " — **not met**")


def coulomb_rows(out, rows):
    goals = {22738: 100, 100000: 300}
    for n in (3505, 22738, 100000):
        j = load(out, f"coulomb-{n}")
        if not j:
            continue
        direct = f"direct {g(j['direct_seconds'])} s" + (" (from a sample of targets)" if j.get("direct_extrapolated") else "")
        goal = f"≥ {goals[n]}×" if n in goals else "—"
        met = j["speedup"] >= goals[n] if n in goals else None
        rows.append(Row(f"Coulomb gradient, n = {n:,} (cat0 surface)", f"coulomb --points {n} --mesh cat0.off",
                        f"FMM {g(j['fast_seconds'])} s, error {j['gradient_rel_error']:.1e}", direct, j["speedup"],
                        goal, met))
    for kind, goal in (("surface", 1.4), ("uniform", 1.4)):
        j = load(out, f"coulomb-1000000-{kind}")
        if j:
            args = "--mesh cat0.off" if kind == "surface" else "--distribution uniform"
            rows.append(Row(f"Coulomb gradient, n = 1,000,000, {kind}", f"coulomb --points 1000000 {args} --repeats 3 --fast-repeats 3",
                            f"FMM {g(j['fast_seconds'])} s, error {j['gradient_rel_error']:.1e}",
                            f"direct ≈ {j['direct_seconds']:.0f} s (extrapolated)", j["speedup"],
                            f"≤ {goal} s (exafmm-t at 3e-4)", j["fast_seconds"] <= goal))
    for n, mesh in ((3505, "cat3505.off"), (22738, "michael22738.off")):
        j = load(out, f"coulomb-iteration-{n}")
        if j:
            rows.append(Row(f"one outer Coulomb iteration (1 step + 1 projection), {n:,} vertices",
                            f"coulomb-iteration --mesh {mesh}",
                            f"{g(j['seconds_per_iteration'])} s (fast sum at 1e-2, the default){spread(j)}; "
                            f"{g(j['seconds_per_iteration_accuracy_1e-3'])} s at 1e-3",
                            f"paper {g(j['paper_seconds_per_iteration'])} s", j["speedup_vs_paper"], "≥ 30×",
                            j["speedup_vs_paper"] >= 30))
    j = load(out, "coulomb-cat0-converged")
    if j:
        s = j.get("seconds", j.get("summary", {}).get("seconds"))
        iters = j.get("iterations", j.get("summary", {}).get("iterations"))
        if s is not None:
            rows.append(Row("converged Coulomb form of cat0 (5,000 vertices), default options",
                            "canon cat0.off -o c.ply --method coulomb --json (its summary)",
                            f"**{s:.2f} s**, {iters} iterations", "—", None, "≤ 1.0 s", s <= 1.0))


def spread(j):
    """' (median of 5 windows of 50 iterations: 0.0061–0.0072 s)' when the bench kept its windows."""
    w = j.get("seconds_per_iteration_windows")
    if not w or len(w) < 2:
        return ""
    return (f" (median of {len(w)} windows of {j.get('repeats', '?')} iterations: "
            f"{g(min(w))}–{g(max(w))} s)")


def other_rows(out, rows, missing):
    for n, mesh, args in ((3505, "cat3505.off", "--anchor-samples 3505 --exact-samples 4"),
                          (22738, "michael22738.off", "--anchor-samples 64 --exact-samples 2 --fmm-samples 32")):
        j = load(out, f"geodesics-{n}")
        if j:
            a = j["anchor"]
            rows.append(Row(f"all-pairs geodesics, {n:,} vertices", f"geodesics --mesh {mesh} {args}",
                            f"heat {g(j['ours']['seconds'])} s", f"CGAL Heat_method_3 {g(a['seconds'])} s"
                            + (" (extrapolated)" if a.get("extrapolated") else ""), j["speedup_vs_anchor"],
                            "≥ 4×" if n == 22738 else "—", j["speedup_vs_anchor"] >= 4 if n == 22738 else None))
    for n in (3505, 22738):
        j = load(out, f"smacof-{n}")
        if not j:
            continue
        ref = j.get("reference", {})
        command = f"smacof --points {n}" + (" --iterations 5" if n == 22738 else "")
        if "speedup_vs_reference" in j:
            ours = f"{g(j['seconds_per_iteration'])} s"
            if "single_thread" in j:
                ours += f" (one thread {g(j['single_thread']['seconds_per_iteration'])} s)"
            rounds = f" (median of {ref['rounds']} rounds)" if ref.get("rounds", 1) > 1 else ""
            rows.append(Row(f"SMACOF iteration, n = {n:,} (Swiss-roll geodesics)", command, ours,
                            f"scikit-learn {ref.get('version', '')} {g(ref['seconds_per_iteration'])} s{rounds}",
                            j["speedup_vs_reference"], "≥ 150×" if n == 3505 else "—",
                            j["speedup_vs_reference"] >= 150 if n == 3505 else None))
        else:
            reason = ref.get("skipped", "not measured")
            rss = j.get("peak_rss_mb")
            ours = f"{g(j['seconds_per_iteration'])} s" + (f", peak RSS {rss / 1024:.2f} GB" if rss else "")
            rows.append(Row(f"SMACOF iteration, n = {n:,}", command, ours, f"scikit-learn: {reason}", None,
                            "≤ 2.5 GB" if n == 22738 else "—", (rss / 1024 <= 2.5) if (rss and n == 22738) else None))
            if n <= 5000:
                missing.append(f"smacof-{n}: {reason}")
    j = load(out, "smacof-cat0-acceleration")
    if j and "acceleration" in j:
        acc = j["acceleration"]
        plain = acc["none"]["iterations"]
        parts = [f"{m.upper()} {acc[m]['iterations']}" for m in ("rre", "mpe") if m in acc]
        best = min(acc[m]["iterations"] for m in ("rre", "mpe") if m in acc)
        rows.append(Row("SMACOF acceleration, cat0", "smacof --mesh cat0.off --acceleration --smacof-tolerance 1e-6",
                        ", ".join(parts) + " iterations", f"plain {plain} iterations", plain / max(best, 1)))
    j = load(out, "icp")
    if j:
        if "ratio_open3d_over_ours" in j:
            rows.append(Row("ICP iteration, cat0 vs cat1", "icp --a cat0.off --b cat1.off",
                            f"{g(j['ours_ms_per_iteration'])} ms",
                            f"Open3D {j['open3d_version']} {g(j['open3d_ms_per_iteration'])} ms",
                            j["ratio_open3d_over_ours"]))
        else:
            reason = j.get("open3d_skipped", "not measured")
            rows.append(Row("ICP iteration, cat0 vs cat1", "icp --a cat0.off --b cat1.off", "—",
                            f"Open3D skipped: {reason}"))
            missing.append(f"icp: {reason}")
    for n in (5000, 22738, 50000):
        for method in ("coulomb", "cmds", "smacof", "lbo", "diffusion", "spectral-mds"):
            j = load(out, f"form-{method}-{n}")
            if not j:
                continue
            mesh = {5000: "cat0.off", 22738: "michael22738.off", 50000: "michael50000.off"}[n]
            ours = f"{g(j['seconds'])} s, {j['peak_rss_mb']:.0f} MB"
            if "speedup_vs_reference" in j:
                ref = j["reference"]
                rows.append(Row(f"{method} form, {j['vertices']:,} vertices", f"form --mesh {mesh} --method {method}",
                                ours, f"full classical MDS {g(ref['seconds'])} s, {ref['peak_rss_mb']:.0f} MB",
                                j["speedup_vs_reference"]))
            else:
                goal = "≤ 60 s, ≤ 2 GB" if n == 50000 else "—"
                met = (j["seconds"] <= 60 and j["peak_rss_mb"] <= 2048) if n == 50000 else None
                rows.append(Row(f"{method} form, {j['vertices']:,} vertices",
                                f"form --mesh {mesh} --method {method} --repeats 1 --reference none", ours,
                                f"({j['reference'].get('skipped', 'not run')})", None, goal, met))
    j = load(out, "main-job")
    if j:
        rows.append(Row("the main job: the paper's experiment on tosca5k, six methods, from nothing",
                        "experiments/run_paper.sh --data ../shared/data/tosca5k (not a bench: timed whole)",
                        f"**{j['seconds'] / 60:.1f} min** ({j['seconds']:.0f} s, build included)", "—", None,
                        "≤ 4 min", j["seconds"] <= 240))


def simd_targets(out):
    found = []
    for target in ("baseline", "avx2", "avx512"):
        if os.path.isdir(os.path.join(out, "simd-" + target)):
            found.append(target)
    return found


def simd_table(out):
    """The dispatched kernels' rows under each instruction set: {row: {target: text}}."""
    table = {}
    for target in simd_targets(out):
        rows = []
        coulomb_rows(os.path.join(out, "simd-" + target), rows)
        d = os.path.join(out, "simd-" + target)
        j = load(d, "smacof-3505")
        if j and "speedup_vs_reference" in j:
            rows.append(Row("SMACOF iteration, n = 3,505", "smacof --points 3505", f"{g(j['seconds_per_iteration'])} s",
                            "scikit-learn", j["speedup_vs_reference"], "≥ 150×", j["speedup_vs_reference"] >= 150))
        for r in rows:
            short = r.ours.split(";")[0].replace("**", "").replace(" (fast sum at 1e-2, the default)", "")
            cell = short + (f" ({ratio_text(r.ratio)})" if r.ratio else "")
            table.setdefault(r.what, {"goal": r.goal})[target] = cell
    return table


def first_line(path):
    try:
        with open(path) as f:
            return f.read().strip()
    except OSError:
        return ""


# The tosca5k comparison across targets (scripts/simd_retrieval.py), measured once per change of the kernels:
# too long for every benchmark run.
SIMD_RETRIEVAL_TIME = "194 s under the baseline, 88 s under AVX2, 90 s under AVX-512"
SIMD_RETRIEVAL = (
    "identical to 3 decimals under baseline, AVX2 and AVX-512, every method and distance (Coulomb: mAP 0.898, "
    "0.834, 0.832 under Hausdorff, Chamfer, RMSE); the 24 Coulomb forms are the same bytes under all three, on "
    "an AMD EPYC")


def median_rows(runs):
    """One row per row of the first run: for a row with a ratio, the row of the run whose ratio is the median
    (the upper median of an even count), with every run's ratio in `runs`; otherwise the first run's row."""
    chosen = []
    for i, first in enumerate(runs[0]):
        same = [rows[i] for rows in runs if i < len(rows) and rows[i].what == first.what]
        with_ratio = [r for r in same if r.ratio]
        if len(same) < 2 or len(with_ratio) != len(same):
            chosen.append(first)
            continue
        ordered = sorted(with_ratio, key=lambda r: r.ratio)
        row = ordered[len(ordered) // 2]
        row.runs = [r.ratio for r in same]
        chosen.append(row)
    return chosen


def markdown(out, rows, run_count=1):
    version = first_line(os.path.join(out, "version.txt")).splitlines()
    build = next((l[len("build: "):] for l in version if l.startswith("build: ")), "unknown")
    kernels = next((l[len("kernels: "):] for l in version if l.startswith("kernels: ")), "unknown")
    p = print
    p("# Benchmarks\n")
    if run_count > 1:
        p(f"Every figure on this page comes from {run_count} runs of `scripts/benchmarks.sh OUT --main-job`, one after the")
        p("other on this project's machine (2 cores, no GPU, otherwise idle), each figure measured in one run together")
        p(f"with its reference. A row with a ratio shows the run of the median ratio, the {run_count} runs' ratios beside it;")
        p("the other rows and tables are the first run's. The page is written from those JSON files by")
        p(f"`scripts/benchmark_ratios.py OUT1 … OUT{run_count} --markdown > docs/benchmarks.md`. The script installs")
    else:
        p("Every figure on this page comes from `scripts/benchmarks.sh OUT --main-job` on this project's machine (2 cores,")
        p("no GPU, otherwise idle), each measured in one run together with its reference, and this page is written from")
        p("those JSON files by `scripts/benchmark_ratios.py OUT --markdown > docs/benchmarks.md`. The script installs")
    p("what is missing (the anchors scikit-learn and Open3D included), builds with the README's commands, writes one")
    p("JSON file per row and prints every ratio. `cat3505`, `michael22738` and `michael50000` are tosca5k's cat0 and")
    p("michael0 remeshed by `cshapes remesh … --vertices N`. The machine is a virtual one on a shared host whose")
    p("speed drifts by up to half over minutes to hours; a drift moves our code and the reference run beside it,")
    p("not always alike, and moves in full the rows timed against a fixed figure (the paper's). The runs' ratios")
    p("beside each figure show the spread. Dated history is in the [changelog](changelog.md).\n")
    p(f"**Build:** {version[0] if version else 'cshapes'}, {build}, the default build (`scripts/build.sh`).  ")
    machine = load(out, "machine")
    if machine:
        p(f"**Processor:** {machine['processor']}, {machine['cores']} cores.  ")
    p(f"**Kernels:** {kernels} — chosen at run time (`cshapes --version`; `CSHAPES_SIMD` forces one).\n")
    p("| what | command (`cshapes -q bench … --json` unless said) | ours | reference, same run | ratio | goal |")
    p("| --- | --- | --- | --- | --- | --- |")
    for r in rows:
        ratio = (f"**{ratio_text(r.ratio)}**" if r.ratio else "—") + runs_text(r)
        p(f"| {r.what} | `{r.command}` | {r.ours} | {r.reference} | {ratio} | {r.goal}{verdict(r.met)} |")
    targets = simd_targets(out)
    if targets:
        table = simd_table(out)
        p("\n## The same rows under each instruction set\n")
        p("The rows whose kernels are dispatched (the Coulomb near field and direct float sum, the metric projection,")
        p("the SMACOF pass), rerun one target after the other in the same `scripts/benchmarks.sh` run with")
        p("`CSHAPES_SIMD=baseline|avx2|avx512` (JSON in `OUT/simd-TARGET/`). Ratios are against the reference of")
        p("each row (direct summation, the paper's timing, scikit-learn).\n")
        p("| what | " + " | ".join(targets) + " | goal |")
        p("| --- | " + " | ".join("---" for _ in targets) + " | --- |")
        for what, cells in table.items():
            p(f"| {what} | " + " | ".join(cells.get(t, "—") for t in targets) + f" | {cells['goal']} |")
    p("\n## Results do not depend on the instruction set beyond these bounds\n")
    p("Each target is deterministic: the same bytes for any thread count. The Coulomb method's kernels (the near")
    p("field, the direct float and double sums, the far field's M2L, the metric projection) perform the same IEEE operations")
    p("in the same order under every target: no fused multiply-adds (their files are compiled with")
    p("`-ffp-contract=off`, so the compiler fuses none either), every sum per target lane in source order, and the")
    p("same hardware estimate of 1/√ (`rsqrtps`, which AVX-512 applies to each half of its registers; SSE2 has it")
    p("too). So on one processor every target gives the same Coulomb bytes. SMACOF's pass keeps its fused")
    p("multiply-adds and eight-lane sums on AVX2 and AVX-512 (the same bytes on both) against the baseline's")
    p("exact 1/√ in a scalar loop. `tests/simd_test.cpp` checks, under every target the CPU supports:\n")
    p("| what | against the baseline |")
    p("| --- | --- |")
    p("| Coulomb gradient: FMM at 1e-3 (the estimate as it is) and at 1e-5 (refined by a Newton step), direct float sum, direct double sum | identical bytes |")
    p("| metric projection (L2 with dilation, L1) | identical bytes |")
    p("| forms of `coulomb` (a posed biped, and an exactly mirror-symmetric input, where any last-bit difference would grow), `cmds`, `lbo`, `diffusion`, `spectral-mds` | identical bytes |")
    p("| SMACOF pass (Guttman transform, uniform and area weights) | relative difference < 1e-5 (AVX-512 runs the AVX2 kernel: the same bytes as AVX2) |")
    p("| forms of `smacof` after the best rigid fit | RMS < 0.1% of the bounding-box diagonal |")
    p("| `experiment paper` retrieval figures (mAP, NN, FT, ST, E, DCG) on a generated set | identical to 3 decimals |")
    p(f"| `experiment paper` retrieval figures on tosca5k, six methods, three distances (`scripts/simd_retrieval.py`, not a test: {SIMD_RETRIEVAL_TIME}) | {SIMD_RETRIEVAL} |")
    p("\nProcessors of different makers differ: `rsqrtps` is specified only to its relative error (1.5·2⁻¹²),")
    p("and Intel's and AMD's tables differ, so the Coulomb forms (and SMACOF's on AVX2 and AVX-512) of one input")
    p("differ between makers, in the last bits at first; on the near-symmetric bodies such a difference can decide")
    p("which of two near-equal forms a pose reaches. No target gives the same Coulomb bytes on every x86-64")
    p("processor; SMACOF's baseline (`CSHAPES_SIMD=baseline`, an exact 1/√) and the other four methods do.")
    p("\n## How the rows are measured\n")
    p("Each `cshapes bench X` command is a thin skin over a library function, `bench_X(XBenchOptions) → XBenchResult`")
    p("with its JSON form `to_json` (`experiments/bench_*.h`), so a C++ program or a test measures what the command")
    p("prints; every JSON names its build and kernels (`build`). An anchor that cannot run (no interpreter with")
    p("scikit-learn or Open3D) is reported as skipped, with the reason. The error columns are relative L2 errors of")
    p("the gradient against direct summation (Coulomb) and mean relative errors against CGAL's exact geodesics")
    p("beyond three edge lengths (geodesics). The Coulomb iteration rows time the canonization's defaults, whose")
    warm_up = (load(out, "coulomb-iteration-3505") or {}).get("warm_up_windows")
    p("fast sum runs at 1e-2 in the iterations, and again at the library-wide 1e-3, in five windows of 50")
    p("iterations each, the two settings taking turns: the figure is the median of the windows' medians, and the")
    p("windows' range is shown, so a few seconds of a slower host move one window rather than the figure." +
      (" Each" if warm_up else " The"))
    if warm_up:
        p("setting runs one untimed window first: the first seconds after an idle spell ran up to a third slower. The")
    p("Coulomb gradient rows time the fast sum 25 times after an untimed run (the first evaluation of a process")
    p("pays for its fresh memory) and the direct sums 5 times, the two taking turns in five rounds, each round's")
    p("fast runs after an untimed one: a slow spell of the host falls on both sides of the ratio. The SMACOF")
    p("row's two sides take turns in three rounds of 10 iterations each, each side's figure the median of its")
    p("rounds (scikit-learn's own time varied from 0.23 to 0.34 s per iteration between runs). The direct")
    p("Coulomb sum, the")
    p("reference of the fast one, is one scalar loop in double precision, the same code and the same bytes under")
    p("every target (the goals were first measured against it). A vectorised direct sum would be about 4× faster")
    p("(gcc once vectorised it for AVX-512 only: 0.24 s against 1.04 s at 22,738 points), and every ratio against")
    p("it about 4× smaller. Small workloads vary by up")
    p("to 30% between runs on this machine; ratios measured in one run hold better than absolute times.")


def collection_section(runs):
    """The section 'A whole collection' from `cshapes experiment retrieval` run folders."""
    p = print
    p("\n## A whole collection\n")
    p("`cshapes experiment retrieval` over a collection, every stage timed by the run itself (the report's \"Where")
    p("the time went\", `retrieval.json`'s `\"profile\"`): wall and CPU seconds (CPU / wall: the cores kept busy).")
    p("The collection is made by `scripts/make_benchmark400.py ../shared/data COLLECTION` (20 classes of 20 shapes")
    p("at 700–28,000 vertices, with near-duplicates and glued shapes); each run starts from an empty output folder.")
    p("This section is written by `scripts/benchmark_ratios.py --collection [LABEL=]RUN ...`; the account below its")
    p("tables by hand.\n")
    for item in runs:
        label, _, run = item.rpartition("=")
        j = json.load(open(os.path.join(run, "retrieval.json")))
        methods = [m["method"] for m in j["methods"]]
        two = j.get("protocol", {}).get("two_stage_k")
        resample = j.get("protocol", {}).get("resample_vertices", 0)
        manifest = "manifest-100.csv" if j["shapes"] == 100 else "manifest.csv"
        command = (f"cshapes experiment retrieval --data COLLECTION/{manifest} --out OUT --methods {','.join(methods)}" +
                   (f" --resample {resample}" if resample else "") + (f" --two-stage-k {two}" if two else ""))
        p(f"**{label + ': ' if label else ''}{j['shapes']} shapes, {len(methods)} methods" +
          (f", two-stage K = {two}" if two else ", exact (all pairs)") + f":** `{command}`\n")
        prof = j.get("profile", [])

        def seconds(stage, method=None):
            rows = [t for t in prof if t["stage"] == stage and (method is None or t["method"] == method or
                                                              method in t["method"].split("+"))]
            return sum(t["wall_seconds"] for t in rows), sum(t["cpu_seconds"] for t in rows), bool(rows)

        def text(w, c, any_rows=True):
            return (f"{w:.0f} s ({c / w:.1f})" if w > 0 else "0 s") if any_rows else "—"

        p("| | forms | pairs | measures | together |")
        p("| --- | ---: | ---: | ---: | ---: |")
        w, c, seen = seconds("resample")
        p(f"| remeshing | | | | {text(w, c, seen)} |")
        for m in methods:
            cells = [seconds(stage, m) for stage in ("forms", "pairs", "measures")]
            p(f"| {m} | " + " | ".join(text(*x) for x in cells) + " | |")
        w, c, seen = seconds("figures")
        p(f"| figures | | | | {text(w, c, seen)} |")
        totals = [seconds(stage) for stage in ("forms", "pairs", "measures")]
        w = sum(t["wall_seconds"] for t in prof)
        c = sum(t["cpu_seconds"] for t in prof)
        p("| **all** | " + " | ".join(text(*x) for x in totals) + f" | **{w / 60:.1f} min** ({c / w:.1f}) |")
        n = j["shapes"]
        if n < 400:  # what the same stages would take on the whole collection: per shape ×400/n, per pair more
            # exact: all n(n-1)/2 pairs; two-stage: about n·K pairs
            pair_factor = 400 / n if two else 400 * 399 / (n * (n - 1))
            scaled = sum(t["wall_seconds"] * (pair_factor if t["stage"] == "pairs" else 400 / n) for t in prof)
            p(f"\nExtrapolated to 400 shapes (remeshes, forms and measures ×{400 / n:g}, pairs ×{pair_factor:.1f}): "
              f"about {scaled / 60:.0f} min.")
        if two:
            recalls = [(m["method"], m.get("two_stage", {}).get("recall_at_k")) for m in j["methods"]]
            if all(r is None for _, r in recalls):
                p("\nrecall@K: not measured (the run was given no exact run of the same collection).")
            else:
                p("\nrecall@K: " + ", ".join(f"{m} {r:.3f}" if r is not None else f"{m} —" for m, r in recalls) +
                  ".")
        p("")
    p("A cell of a method's forms shared with another (classical MDS and SMACOF compute each shape's geodesic")
    p("matrix once for both) shows their joint stage in both columns.")


def main(argv):
    args = argv[1:]
    collections = []
    while "--collection" in args:
        k = args.index("--collection")
        if k + 1 >= len(args):
            print(__doc__, file=sys.stderr)
            return 2
        collections.append(args[k + 1])
        del args[k:k + 2]
    as_markdown = bool(args) and args[-1] == "--markdown"
    outs = args[:-1] if as_markdown else args
    if not outs and collections:  # the section alone, to update the page's section by itself
        collection_section(collections)
        return 0
    if not outs or any(o.startswith("--") for o in outs):
        print(__doc__, file=sys.stderr)
        return 2
    runs, missing = [], []
    for i, out in enumerate(outs):
        rows = []
        coulomb_rows(out, rows)
        other_rows(out, rows, missing if i == 0 else [])
        runs.append(rows)
    rows = median_rows(runs)
    out = outs[0]
    if as_markdown:
        markdown(out, rows, len(outs))
        if collections:
            collection_section(collections)
    else:
        print(f"{'row':60s} {'ours':>40s}   {'reference, same run':>40s}   ratio")
        for r in rows:
            ratio = (ratio_text(r.ratio) if r.ratio else "—") + runs_text(r)
            print(f"{r.what:60s} {r.ours:>40s}   {r.reference:>40s}   {ratio:>8s}  {r.goal}{verdict(r.met)}")
        for what, cells in simd_table(out).items():
            print(f"{what:60s} " + "   ".join(f"{t}: {c}" for t, c in cells.items() if t != "goal"))
        if collections:
            collection_section(collections)
    for m in missing:
        print(f"benchmark_ratios: an anchor did not run: {m} (scripts/install-deps.sh --with-anchors)",
              file=sys.stderr)
    return 1 if missing else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
