#!/usr/bin/env python3
"""Merge the per-plant tables of several `sets-diagnose --suite random` reports (chunks of a long
campaign run one after the other or side by side) into the suite's summary figures, as
`suite_report` (src/examples/diagnosis_suite.cpp) computes them for one run: one-effect plants
first named right, two-effect plants both named, invented effects on clean plants, true values
inside the bounded-error interval and the estimate, the noise ratio's distribution, the confusion
matrix, per-effect precision and recall, and the headline figures per plant family. The "meet"
figure is not in the table and is left out.
The declared lenient figures (right, or the truth among the named effects' equally good
alternatives) and the alternatives per named effect come from the "Equally good on these data"
table (reports without it: no alternatives).

    python3 scripts/merge_suite_reports.py held_*.md
"""
import re
import sys
from collections import Counter, defaultdict

EFFECT = re.compile(r"(?:^|, )([a-z_0-9]+) \(")


def effects(cell):
    """Effect names of a 'name (where, ...)' list, in order ('none': no effect)."""
    return [] if cell.strip() == "none" else EFFECT.findall(cell.strip())


def table(paths, width):
    """The rows of the tables `width` cells wide whose first cell is a random plant."""
    for path in paths:
        with open(path) as f:
            for line in f:
                cells = [c.strip() for c in line.strip().strip("|").split("|")]
                if len(cells) == width and cells[0].startswith("random-"):
                    yield path, cells


def rows(paths):
    seen = set()
    for path, cells in table(paths, 11):
        if cells[0] in seen:
            sys.exit(f"{path}: plant {cells[0]} appears twice")
        seen.add(cells[0])
        yield path, cells


def equally_good(paths):
    """Per plant, per named rank: (alternatives listed, true effects among them)."""
    out = defaultdict(dict)
    for _, cells in table(paths, 5):
        rank = int(cells[2].split(".", 1)[0])
        among = set() if cells[4] == "none" else set(x.strip() for x in cells[4].split(","))
        out[cells[0]][rank] = (len(cells[3].split("; ")), among)
    return out


def pct(k, n):
    return f"{k} of {n} ({100.0 * k / n:.1f} %)" if n else f"{k} of {n}"


def main(paths):
    if not paths:
        sys.exit(__doc__)
    n = one = one_right = two = two_both = two_one = clean = invented = nothing = failed = 0
    bounded = inside = cov = inside_estimate = 0
    seconds = 0.0
    ratios, ratios_nominal, misses = [], [], []
    confusion = defaultdict(Counter)
    tp, fp, fn = Counter(), Counter(), Counter()
    family = defaultdict(Counter)  # per family: one, one_right, two, two_both, clean, invented
    alike = equally_good(paths)
    one_lenient = two_lenient = named_effects = listed = plants_listing = 0
    for path, c in rows(paths):
        n += 1
        truth, named = effects(c[2]), effects(c[3])
        answer = c[4]
        seconds += float(c[10])
        if answer.startswith("error"):
            failed += 1
        # Per output "final" or "final (nominal's)" (older chunks: one value, the nominal's).
        for m in re.finditer(r"([-+\d.e]+)(?:\s*\(([-+\d.e]+)\))?", c[8]):
            ratios.append(float(m[1]))
            ratios_nominal.append(float(m[2] or m[1]))
        m = re.match(r"(\d+) of (\d+); (\d+) of (\d+)", c[9])
        if m:
            inside += int(m[1]); bounded += int(m[2]); inside_estimate += int(m[3]); cov += int(m[4])
        mine = alike.get(c[0], {})
        among = set().union(*(a for _, a in mine.values())) if mine else set()
        named_effects += len(named)
        listed += sum(k for k, _ in mine.values())
        plants_listing += bool(mine)
        fam = family[c[1]]
        if not truth:
            clean += 1
            invented += bool(named)
            fam["clean"] += 1
            fam["invented"] += bool(named)
            nothing += answer == "nothing_missing"
        elif len(truth) == 1:
            one += 1
            right = c[5] == "yes"
            one_right += right
            fam["one"] += 1
            fam["one_right"] += right
            one_lenient += right or truth[0] in mine.get(1, (0, set()))[1]
            if not right:
                misses.append(f"{c[0]}: {c[2]} -> named {c[3]} ({answer})")
        else:
            two += 1
            two_both += c[6] == "yes"
            fam["two"] += 1
            fam["two_both"] += c[6] == "yes"
            two_lenient += all(t in named or t in among for t in truth)
            two_one += any(t in named for t in truth)
        if len(truth) <= 1:
            confusion[truth[0] if truth else "none"][named[0] if named else "none"] += 1
        for t in truth:
            (tp if t in named else fn)[t] += 1
        for x in named:
            if x not in truth:
                fp[x] += 1
    print(f"Plants: {n} ({one} with one effect, {two} with two, {clean} clean; {failed} failed); "
          f"{seconds:.1f} s of diagnosis in all\n")
    print(f"- one-effect plants, first named right: {pct(one_right, one)}")
    print(f"- two-effect plants, both named: {pct(two_both, two)} (at least one: {pct(two_one, two)})")
    print("- declared second figures, lenient: right or the truth among the named effects' equally good alternatives "
          f"(one-effect: the first named effect's): one-effect {pct(one_lenient, one)}, two-effect both "
          f"{pct(two_lenient, two)}; alternatives listed: {listed} for {named_effects} named effects "
          f"({listed / named_effects if named_effects else 0:.2f} per named effect), on {plants_listing} plants")
    print(f"- clean plants with an invented effect: {pct(invented, clean)} "
          f"(answered \"no physics is missing\": {pct(nothing, clean)})")
    print(f"- true values with a bounded-error interval: {pct(bounded, cov)}; inside it: {pct(inside, bounded)}")
    print(f"- inside the estimate (output-error PUI linearised at the estimate): {pct(inside_estimate, cov)}")
    for values, label in ((ratios, "final model's residual"),
                          (ratios_nominal, "calibrated nominal's residual (the rules' floor)")):
        if not values:
            continue
        r = sorted(values)
        q = lambda f: r[int(f * (len(r) - 1))]
        within = sum(0.5 <= x <= 2 for x in r)
        print(f"- estimated / true noise level, {label} ({len(r)} outputs): median {q(0.5):.2f}, 10 % {q(0.1):.2f}, "
              f"90 % {q(0.9):.2f}, lowest {r[0]:.2f}, highest {r[-1]:.2f}; within a factor 2: {pct(within, len(r))} "
              f"({sum(x < 0.5 for x in r)} under 0.5, {sum(x > 2 for x in r)} over 2)")
    labels = sorted(set(confusion) | {c for row in confusion.values() for c in row})
    print("\nConfusion matrix (one-effect and clean plants; rows: true effect, columns: first named):\n")
    print("| true \\ named | " + " | ".join(labels) + " |")
    print("| --- |" + " --- |" * len(labels))
    for row in labels:
        if row in confusion:
            print(f"| {row} | " + " | ".join(str(confusion[row][col] or "") for col in labels) + " |")
    print("\nPer effect (all plants):\n\n| effect | true | named right | precision | recall |\n| --- | --- | --- | --- | --- |")
    for e in sorted(set(tp) | set(fp) | set(fn)):
        print(f"| {e} | {tp[e] + fn[e]} | {tp[e]} | {pct(tp[e], tp[e] + fp[e])} | {pct(tp[e], tp[e] + fn[e])} |")
    print("\nPer family (the headline figures of each plant family):\n\n| family | one-effect, first named right | "
          "two-effect, both named | clean, invented effect |\n| --- | --- | --- | --- |")
    for name in sorted(family):
        f = family[name]
        print(f"| {name} | {pct(f['one_right'], f['one'])} | {pct(f['two_both'], f['two'])} | {pct(f['invented'], f['clean'])} |")
    print("\nOne-effect plants not first named right:\n")
    for m in misses:
        print(f"- {m}")


if __name__ == "__main__":
    main(sys.argv[1:])
