#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The skip gate: a skipped test is never a silent pass.

usage: check.py ENV JUNIT.xml [EXPECTED]

Reads the JUnit file ctest wrote (ctest --output-junit), prints every skipped test with its
reason, and exits 1 when one of them is not on the expected-skip list (tests/skips/expected.txt
by default) for environment ENV (the ctest preset: default, asan, aarch64, armhf, ...).
Exits 2 when the JUnit file is missing or unreadable (a gate that cannot read is not a pass).
"""
import fnmatch
import os
import sys
import xml.etree.ElementTree as ET


def read_expected(path):
    """[(pattern, {env...}, reason, line)] from PATH; malformed lines are an error."""
    rules = []
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            text = line.strip()
            if not text or text.startswith("#"):
                continue
            fields = [x.strip() for x in text.split(" | ")]
            if len(fields) != 3 or not all(fields):
                sys.exit(f"{path}:{number}: line = '{text}', expected 'PATTERN | ENV,ENV | REASON'")
            envs = {e.strip() for e in fields[1].split(",") if e.strip()}
            rules.append((fields[0], envs, fields[2], number))
    return rules


def skip_reason(case):
    """The reason GoogleTest printed after 'Skipped' (or ctest's message), one line."""
    out = case.findtext("system-out") or ""
    lines = out.splitlines()
    for i, line in enumerate(lines):
        if line.rstrip().endswith("Skipped") and i + 1 < len(lines) and lines[i + 1].strip():
            return lines[i + 1].strip()
    skipped = case.find("skipped")
    if skipped is not None and skipped.get("message"):
        return skipped.get("message")
    return "(no reason printed)"


def main(argv):
    if len(argv) not in (3, 4):
        sys.exit(__doc__)
    env, junit = argv[1], argv[2]
    expected = argv[3] if len(argv) == 4 else os.path.join(os.path.dirname(__file__), "expected.txt")
    rules = read_expected(expected)
    try:
        root = ET.parse(junit).getroot()
    except (OSError, ET.ParseError) as e:
        print(f"skip gate ({env}): cannot read {junit}: {e}", file=sys.stderr)
        return 2
    cases = list(root.iter("testcase"))
    skipped = [c for c in cases if c.find("skipped") is not None or c.get("status") in ("notrun", "disabled")]
    unexpected = []
    used = set()
    print(f"skips ({env}): {len(skipped)} of {len(cases)} tests")
    for case in skipped:
        name = case.get("name", "?")
        rule = next((r for r in rules if env in r[1] and fnmatch.fnmatchcase(name, r[0])), None)
        if rule:
            used.add(rule[3])
            print(f"  expected    {name}: {rule[2]}")
        else:
            unexpected.append(name)
            print(f"  UNEXPECTED  {name}: {skip_reason(case)}")
    if unexpected:
        print(f"skip gate ({env}): {len(unexpected)} unexpected skip(s); run them or add them, with the "
              f"reason and the environment, to {expected}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
