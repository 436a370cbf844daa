#!/usr/bin/env python3
"""Issue 57's probe: hostile inputs generated from a seed, each checked against the rule that fixes it.

  scripts/trust_probe.py [--cshapes build/cshapes] [--seed 1] [--count 40] [--keep DIR]

Each case is drawn from one of the families below (degenerate and far-scaled sets in ICP, tied distance
matrices, outputs over a user's files, manifest entries outside the dataset, cache entries of the old format,
PLY headers with wrong counts, NUL bytes in a CSV field) with its parameters from the seed, so a run is
reproducible and nothing is stored. A case passes when the CLI follows the rule: never killed by a signal, the
documented exit code, a message naming the cause, nothing of a user's replaced, nothing of a file that is not
a mesh printed, and results that do not depend on the order of the shapes. Failing cases are kept under
--keep (default: a temporary folder, printed) with the command that failed. Exits 1 when any case fails.
Standard library only; tests/python/test_trust_probe.py runs a seeded sample.
"""
import argparse
import json
import os
import random
import shutil
import subprocess
import sys
import tempfile


class Case:
    def __init__(self, family, folder, cli):
        self.family, self.folder, self.cli = family, folder, cli
        self.problems = []
        self.commands = []

    def run(self, *args, cwd=None):
        command = [self.cli, "-q", *args]
        self.commands.append(" ".join(command))
        r = subprocess.run(command, capture_output=True, cwd=cwd or self.folder, timeout=600)
        r.stdout_text = r.stdout.decode("utf-8", "replace")
        r.stderr_text = r.stderr.decode("utf-8", "replace")
        if r.returncode < 0:
            self.problems.append(f"killed by signal {-r.returncode}: {' '.join(command)}")
        return r

    def expect(self, condition, what):
        if not condition:
            self.problems.append(what)


def write(path, text):
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", newline="") as f:
        f.write(text)


def off_points(points):
    return "OFF\n%d 0 0\n" % len(points) + "".join("%.17g %.17g %.17g\n" % p for p in points)


def random_cloud(rng, n):
    return [(rng.gauss(0, 1), rng.gauss(0, 0.6), rng.gauss(0, 0.3)) for _ in range(n)]


# ---- the families ----

def icp_degenerate(case, rng):
    """A set that spans no plane (one point, copies of one point, points on a line) aligned with a cloud."""
    kind = rng.choice(["one point", "copies", "line"])
    n = 1 if kind == "one point" else rng.randint(2, 60)
    p = (rng.uniform(-5, 5), rng.uniform(-5, 5), rng.uniform(-5, 5))
    if kind == "line":
        d = (rng.gauss(0, 1), rng.gauss(0, 1), rng.gauss(0, 1))
        points = [tuple(p[k] + t * d[k] for k in range(3)) for t in (rng.uniform(-1, 1) for _ in range(n))]
    else:
        points = [p] * n
    write(os.path.join(case.folder, "bad.off"), off_points(points))
    write(os.path.join(case.folder, "cloud.off"), off_points(random_cloud(rng, 200)))
    first, second = ("bad.off", "cloud.off") if rng.random() < 0.5 else ("cloud.off", "bad.off")
    r = case.run("align", first, second, "--json")
    case.expect(r.returncode == 1, f"{kind} ({n}): exit {r.returncode}, expected 1 (refused)")
    case.expect("bad.off" in r.stderr_text, f"{kind}: the message does not name bad.off: {r.stderr_text!r}")


def icp_far_scale(case, rng):
    """A cloud aligned with itself scaled by 10^e, |e| up to 300: works, the distance scales with the set."""
    exponent = rng.choice([-1, 1]) * rng.randint(20, 300)
    cloud = random_cloud(rng, 300)
    scale = 10.0 ** exponent
    write(os.path.join(case.folder, "a.off"), off_points(cloud))
    write(os.path.join(case.folder, "b.off"), off_points([tuple(scale * x for x in p) for p in cloud]))
    r = case.run("align", "a.off", "b.off", "--json")
    case.expect(r.returncode in (0, 1), f"scale 1e{exponent}: exit {r.returncode}")
    if r.returncode == 1:
        case.expect("b.off" in r.stderr_text or "a.off" in r.stderr_text,
                    f"scale 1e{exponent}: the refusal names no set: {r.stderr_text!r}")


def tied_matrix(n, classes, value):
    names = ["%s%d" % (c, i) for c in classes for i in range(n // len(classes))]
    rows = [",".join([""] + names)]
    for a in names:
        rows.append(",".join([a] + ["0" if a == b else value for b in names]))
    return names, "\n".join(rows) + "\n"


def evaluate_ties(case, rng):
    """A matrix of tied distances: the measures do not depend on the order of the shapes."""
    k = rng.randint(2, 4)
    classes = ["abcdefgh"[i] * 3 for i in range(k)]
    per_class = rng.randint(3, 5)
    value = rng.choice(["0", "1", "inf", "%.6g" % rng.uniform(0.1, 10)])
    names, text = tied_matrix(per_class * k, classes, value)
    write(os.path.join(case.folder, "D.csv"), text)
    order = names[:]
    rng.shuffle(order)
    rows = [",".join([""] + order)]
    for a in order:
        rows.append(",".join([a] + ["0" if a == b else value for b in order]))
    write(os.path.join(case.folder, "P.csv"), "\n".join(rows) + "\n")
    results = []
    for name in ("D", "P"):
        r = case.run("evaluate", name + ".csv", "--out", "eval_" + name, "--no-draw", "--json")
        case.expect(r.returncode == 0, f"evaluate {name}.csv: exit {r.returncode}: {r.stderr_text}")
        try:
            results.append(json.loads(r.stdout_text))
        except ValueError:
            case.problems.append(f"evaluate {name}.csv --json: not JSON")
            return
    a, b = results
    for key in ("map", "nn", "ft", "st", "e", "dcg"):
        if key in a.get("mean", a) and key in b.get("mean", b):
            x, y = a.get("mean", a)[key], b.get("mean", b)[key]
            case.expect(x is not None and y is not None and abs(x - y) <= 1e-9,
                        f"value {value}: {key} {x} in matrix order, {y} after a permutation")


def outputs_over_user_files(case, rng):
    """generate and evaluate never replace a user's file, and leave no partial set."""
    kind = rng.choice(["dataset", "hand", "swissroll", "evaluate"])
    mine = "a user's bytes %d\n" % rng.randint(0, 10 ** 9)
    if kind == "dataset":
        victim = os.path.join(case.folder, "mydata", rng.choice(["biped0.off", "manifest.csv", "notes.txt"]))
        write(victim, mine)
        r = case.run("generate", "dataset", "--out", "mydata", "--classes", "1", "--poses", "2", "--noisy", "0",
                     "--vertices", "300")
    elif kind == "hand":
        victim = os.path.join(case.folder, "h", rng.choice(["hand_glued.off", "hand_separated.off"]))
        write(victim, mine)
        r = case.run("generate", "hand", "--out", "h")
    elif kind == "swissroll":
        victim = os.path.join(case.folder, "swissroll.off")
        write(victim, mine)
        r = case.run("generate", "swissroll")
    else:
        _, text = tied_matrix(6, ["aaa", "bbb"], "1")
        write(os.path.join(case.folder, "D.csv"), text)
        victim = os.path.join(case.folder, "e", rng.choice(["metrics.json", "pr.png", "mine.txt"]))
        write(victim, mine)
        r = case.run("evaluate", "D.csv", "--out", "e", "--no-draw")
    case.expect(r.returncode == 1, f"{kind} over {os.path.basename(victim)}: exit {r.returncode}, expected 1")
    with open(victim) as f:
        case.expect(f.read() == mine, f"{kind}: {os.path.basename(victim)} was replaced")


def manifest_outside(case, rng):
    """A manifest entry leading outside the dataset's folder is refused, and nothing of it is printed."""
    secret = "secret-%d:x:0:0:root" % rng.randint(0, 10 ** 9)
    write(os.path.join(case.folder, "secret.off"), secret + "\n")
    r = case.run("generate", "dataset", "--out", "data", "--classes", "1", "--poses", "3", "--noisy", "0",
                 "--vertices", "300")
    case.expect(r.returncode == 0, f"generate dataset: exit {r.returncode}: {r.stderr_text}")
    kind = rng.choice(["dotdot", "absolute", "link"])
    if kind == "dotdot":
        entry = "../" * rng.randint(1, 1) + "secret.off"
    elif kind == "absolute":
        entry = os.path.join(case.folder, "secret.off")
    else:
        os.symlink(os.path.join(case.folder, "secret.off"), os.path.join(case.folder, "data", "link.off"))
        entry = "link.off"
    with open(os.path.join(case.folder, "data", "manifest.csv")) as f:
        lines = f.read().splitlines()
    columns = lines[0].split(",")
    row = {"file": entry, "class": "biped", "pose": "9", "noisy": "0"}
    lines.insert(rng.randint(1, len(lines)), ",".join(row[c] for c in columns))
    write(os.path.join(case.folder, "data", "manifest.csv"), "\n".join(lines) + "\n")
    r = case.run("distmat", "data/manifest.csv", "-o", "D.csv", "--method", "lbo")
    case.expect(r.returncode == 1, f"{kind}: exit {r.returncode}, expected 1")
    case.expect(secret not in r.stderr_text + r.stdout_text, f"{kind}: the file's content was printed")
    case.expect("--allow-outside" in r.stderr_text, f"{kind}: no hint of --allow-outside: {r.stderr_text!r}")


def ply_wrong_count(case, rng):
    """A PLY header claiming more vertices than the file holds: the message names the claim."""
    r = case.run("generate", "swissroll", "-o", "s.off", "--vertices", str(rng.randint(100, 600)))
    binary = rng.random() < 0.5
    args = ["convert", "s.off", "s.ply"] + (["--binary"] if binary else [])
    r = case.run(*args)
    if r.returncode != 0:  # no --binary flag: ASCII only
        r = case.run("convert", "s.off", "s.ply")
        binary = False
    with open(os.path.join(case.folder, "s.ply"), "rb") as f:
        data = f.read()
    head, _, rest = data.partition(b"element vertex ")
    count, _, tail = rest.partition(b"\n")
    claimed = int(count) + rng.randint(1, 40)
    with open(os.path.join(case.folder, "bad.ply"), "wb") as f:
        f.write(head + b"element vertex " + str(claimed).encode() + b"\n" + tail)
    r = case.run("info", "bad.ply")
    case.expect(r.returncode == 1, f"binary={binary}: exit {r.returncode}, expected 1")
    case.expect("claims" in r.stderr_text and str(claimed) in r.stderr_text,
                f"binary={binary}: the message does not name the claimed count {claimed}: {r.stderr_text!r}")


def nul_in_field(case, rng):
    """A NUL byte in a CSV field: the message goes on past it."""
    n = rng.randint(3, 6)
    names = ["s%d" % i for i in range(n)]
    rows = [[""] + names] + [[a] + ["0" if a == b else "1" for b in names] for a in names]
    i, j = rng.randint(1, n), rng.randint(1, n)
    rows[i][j] = "x\0" + "y"
    with open(os.path.join(case.folder, "D.csv"), "wb") as f:
        f.write(("\n".join(",".join(r) for r in rows) + "\n").encode())
    r = case.run("evaluate", "D.csv", "--out", "e", "--no-draw")
    case.expect(r.returncode == 1, f"exit {r.returncode}, expected 1")
    case.expect("\\x00y" in r.stderr_text, f"the message stops at the NUL byte: {r.stderr_text!r}")


FAMILIES = [icp_degenerate, icp_far_scale, evaluate_ties, outputs_over_user_files, manifest_outside,
            ply_wrong_count, nul_in_field]


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cshapes", default=os.path.join(root, "build", "cshapes"))
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--count", type=int, default=40)
    parser.add_argument("--keep", default="")
    args = parser.parse_args()
    cli = os.path.abspath(args.cshapes)
    keep = args.keep or tempfile.mkdtemp(prefix="cshapes-trust-probe-")
    rng = random.Random(args.seed)
    failed = 0
    counts = {}
    for index in range(args.count):
        family = FAMILIES[index % len(FAMILIES)] if index < len(FAMILIES) else rng.choice(FAMILIES)
        case_rng = random.Random(rng.getrandbits(64))
        folder = tempfile.mkdtemp(prefix="case-")
        case = Case(family.__name__, folder, cli)
        try:
            family(case, case_rng)
        except subprocess.TimeoutExpired as e:
            case.problems.append(f"timed out: {e.cmd}")
        passed, total = counts.get(case.family, (0, 0))
        if case.problems:
            failed += 1
            target = os.path.join(keep, "%03d-%s" % (index, case.family))
            shutil.copytree(folder, target, symlinks=True)
            with open(os.path.join(target, "commands.txt"), "w") as f:
                f.write("\n".join(case.commands) + "\n")
            print(f"FAIL case {index} ({case.family}): " + "; ".join(case.problems) + f" [kept in {target}]")
        counts[case.family] = (passed + (0 if case.problems else 1), total + 1)
        shutil.rmtree(folder, ignore_errors=True)
    for family, (passed, total) in sorted(counts.items()):
        print(f"{family:26s} {passed}/{total} passed")
    print(f"trust probe: seed {args.seed}, {args.count} cases, {failed} failed")
    if not failed and not args.keep:
        shutil.rmtree(keep, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
