#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""One way to say what was wrong (issue 24 §5, base/config/error.hpp): every message names
"FIELD = VALUE, expected WHAT". Usage: check_message_form.py [ROOT]; reads the string
literals of base/, hal/, firmware/, sim/ and host/ and prints each one that says
"; expected" or ": expected" as FILE:LINE: the literal; exit 1 if any."""
import pathlib
import re
import sys

ROOMS = ("base", "hal", "firmware", "sim", "host")
# A literal whose text before "expected" ends in ';' or ':' (a literal split over lines
# starts with the punctuation: "; expected …").
OTHER_FORM = re.compile(r'"(?:[^"\\]|\\.)*?[;:] expected')


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".")
    found = 0
    files = 0
    for room in ROOMS:
        for path in sorted((root / room).rglob("*")):
            if path.suffix not in (".cpp", ".hpp") or not path.is_file():
                continue
            files += 1
            for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
                if line.lstrip().startswith("//"):
                    continue
                match = OTHER_FORM.search(line)
                if match:
                    found += 1
                    print(f"{path.relative_to(root)}:{number}: {match.group(0)}… "
                          "says it another way: expected \", expected\" after FIELD = VALUE")
    print(f"check_message_form: {found} message{'s' if found != 1 else ''} in another form, "
          f"{files} files read")
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
