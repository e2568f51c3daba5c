"""scripts/merge_suite_reports.py: chunks of a `sets-diagnose --suite random` campaign merged into
the suite's figures, the headline per plant family among them (rows written by hand in the plant
table's format: no diagnosis run)."""

import pathlib
import subprocess
import sys

SCRIPT = pathlib.Path(__file__).resolve().parents[2] / "scripts" / "merge_suite_reports.py"
HEADER = ("| plant | family | true effects (where, strength) | named (where) | answer | first right | all named | "
          "fit val: nominal -> augmented | noise est/true: final (nominal's if different) | "
          "true values inside: bounded-error; estimate | s |\n"
          "| --- | --- | --- | --- | --- | --- | --- | --- | --- | --- | --- |\n")


def row(plant, family, truth, named, answer, first, both):
    return (f"| random-{plant} | {family} | {truth} | {named} | {answer} | {first} | {both} | 90.0 -> 99.0 | 1.00 | "
            "0 of 0; 1 of 1 | 2.0 |\n")


def merged(tmp_path, chunks):
    paths = []
    for k, rows in enumerate(chunks):
        p = tmp_path / f"held_{k}.md"
        p.write_text(HEADER + "".join(rows))
        paths.append(str(p))
    return subprocess.run([sys.executable, str(SCRIPT), *paths], check=True, capture_output=True, text=True).stdout


def test_each_plant_counts_in_its_familys_row_by_the_headline_rules(tmp_path):
    out = merged(tmp_path, [
        [row(1, "position_loop", "dead_zone (u, 20 %, 6 sigma)", "dead_zone (u)", "missing", "yes", "yes"),
         row(2, "position_loop", "coulomb_friction (v, 20 %, 6 sigma)", "dead_zone (u)", "missing", "**no**", "**no**")],
        [row(3, "position_loop", "none", "constant_offset (v)", "missing", "**no**", "yes"),
         row(4, "tanks", "dead_zone (q, 20 %, 6 sigma), constant_offset (h, 20 %, 6 sigma)",
             "constant_offset (h), dead_zone (q)", "missing", "**no**", "yes"),
         row(5, "tanks", "none", "none", "nothing_missing", "yes", "yes")],
    ])
    assert "| position_loop | 1 of 2 (50.0 %) | 0 of 0 | 1 of 1 (100.0 %) |" in out, out
    assert "| tanks | 0 of 0 | 1 of 1 (100.0 %) | 0 of 1 (0.0 %) |" in out, out
    # The totals are the families' sums.
    assert "one-effect plants, first named right: 1 of 2 (50.0 %)" in out, out
    assert "clean plants with an invented effect: 1 of 2 (50.0 %)" in out, out


def test_a_plant_in_two_chunks_is_an_error(tmp_path):
    one = row(1, "tanks", "none", "none", "nothing_missing", "yes", "yes")
    p, q = tmp_path / "a.md", tmp_path / "b.md"
    p.write_text(HEADER + one)
    q.write_text(HEADER + one)
    r = subprocess.run([sys.executable, str(SCRIPT), str(p), str(q)], capture_output=True, text=True)
    assert r.returncode != 0
    assert "random-1 appears twice" in r.stderr
