#!/usr/bin/env python3
"""Checks that tests/ mirrors src/ path for path (docs/architecture.md, GUIDE "tests/ mirrors").

Every library source src/<path>.cpp needs tests/<path>_test.cpp, and that file must hold at least
one GoogleTest/RapidCheck test with an assertion (a test that can fail). A source that truly
cannot be tested alone goes into ALLOWED with the reason; the check fails if an allowed source
has since got its test file, so the list only shrinks.

    python3 scripts/check_test_mirror.py           # exit 1 and one line per source without its test
    python3 scripts/check_test_mirror.py --list    # every source with the test file that covers it
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent

# src/<path>.cpp -> why it has no tests/<path>_test.cpp of its own.
ALLOWED = {
}

TEST_MACRO = re.compile(r"^\s*(TEST|TEST_F|TEST_P|RC_GTEST_PROP|RC_GTEST_FIXTURE_PROP)\s*\(", re.M)
ASSERTION = re.compile(r"\b(EXPECT_|ASSERT_|RC_ASSERT|RC_SUCCEED_IF|RC_FAIL|FAIL\s*\(|ADD_FAILURE)")


def sources():
    for path in sorted((ROOT / "src").rglob("*.cpp")):
        yield path.relative_to(ROOT / "src")


def test_file_of(rel):
    return ROOT / "tests" / rel.parent / f"{rel.stem}_test.cpp"


def problem_of(rel):
    """None when src/<rel> has a test file of its name that holds a test able to fail."""
    test = test_file_of(rel)
    if not test.is_file():
        return f"src/{rel}: no test file {test.relative_to(ROOT)}"
    text = test.read_text(errors="replace")
    if not TEST_MACRO.search(text):
        return f"{test.relative_to(ROOT)}: no TEST/TEST_F/TEST_P/RC_GTEST_PROP"
    if not ASSERTION.search(text):
        return f"{test.relative_to(ROOT)}: no assertion (EXPECT_/ASSERT_/RC_ASSERT): nothing can fail"
    return None


def main(argv):
    problems, seen = [], set()
    for rel in sources():
        key = str(rel)
        seen.add(key)
        problem = problem_of(rel)
        if "--list" in argv:
            print(f"{key:<45} {'ALLOWED: ' + ALLOWED[key] if key in ALLOWED else problem or test_file_of(rel).relative_to(ROOT)}")
        if key in ALLOWED:
            if problem is None:
                problems.append(f"src/{key}: has its test file now; remove it from ALLOWED in {pathlib.Path(__file__).name}")
        elif problem:
            problems.append(problem)
    for key in ALLOWED:
        if key not in seen:
            problems.append(f"ALLOWED names src/{key}, which does not exist; remove it")
    for p in problems:
        print(p, file=sys.stderr)
    if problems:
        print(f"{len(problems)} problem(s); tests/ must mirror src/ path for path "
              f"(src/a/b.cpp -> tests/a/b_test.cpp)", file=sys.stderr)
    return 1 if problems else 0


if __name__ == "__main__":
    try:
        sys.exit(main(sys.argv[1:]))
    except BrokenPipeError:  # --list | head
        sys.exit(0)
