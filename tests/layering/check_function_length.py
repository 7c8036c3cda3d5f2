#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""Functions stay short (issue 38 §4 and §5). No function body in base/, hal/ or firmware/ is
longer than LIMIT lines. In host/ and sim/ there are no more such functions than HOST_SIM_ALLOWED,
the count when issue 38 closed. That is a ratchet: a new long function there fails, and a long
function that is split lowers the number here.

Usage: check_function_length.py [ROOT]. Prints each function over the limit as
FILE:LINE: NAME (N lines), then a summary. Exits 1 when base/, hal/ or firmware/ has one, or
when host/ and sim/ have more than allowed.

A function is found by its header, not by a C++ parser. The header is the statement that
ends in the `{` opening its body, has a `(`, and is not a control statement, a lambda, an
initialiser or a class. Its body runs to the matching `}`, counted with comments, string and
character literals removed. Lambdas and class bodies inside a function count as part of it."""
import pathlib
import re
import sys

LIMIT = 80
STRICT = ("base", "hal", "firmware")
RATCHETED = ("host", "sim")
HOST_SIM_ALLOWED = 11
CONTROL = re.compile(r"^(if|for|while|switch|else|do|catch|try|return|namespace|class|struct|"
                     r"enum|union|template\s*<[^>]*>\s*(class|struct))\b")
NAME = re.compile(r"([~\w:]+(?:<[^()]*>)?|operator\s*[^\s(]+)\s*\($")


def code_only(text):
    """The text with comments, string and character literals blanked (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            i = n if j < 0 else j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append("\n" * text.count("\n", i, j))
            i = j
        elif text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == "_")):
            k = text.find("(", i)
            delimiter = ")" + text[i + 2:k] + '"'
            j = text.find(delimiter, k)
            j = n if j < 0 else j + len(delimiter)
            out.append('""' + "\n" * text.count("\n", i, j))
            i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(c + c)
            i = j + 1
        else:
            out.append(c)
            i += 1
    return "".join(out)


def long_functions(path, relative):
    lines = code_only(path.read_text(errors="replace")).split("\n")
    found = []
    header = ""
    i = 0
    while i < len(lines):
        line = lines[i].strip()
        if line.startswith("#"):
            i += 1
            continue
        header = (header + " " + line).strip()
        if line.endswith("{"):
            before_brace = header[:-1].rstrip()
            head = before_brace.split("(")[0]
            is_function = ("(" in before_brace and not CONTROL.match(header)
                           and "=" not in head and "[" not in head)
            if is_function:
                depth, j = 0, i
                while j < len(lines):
                    depth += lines[j].count("{") - lines[j].count("}")
                    if depth <= 0:
                        break
                    j += 1
                body = j - i - 1
                if body > LIMIT:
                    match = NAME.search(head.rstrip() + "(")
                    name = match.group(1) if match else head.split()[-1]
                    found.append((relative, i + 1, name, body))
                header = ""
                i = j + 1
                continue
            header = ""
        elif line.endswith((";", "}")) or not line:
            header = ""
        i += 1
    return found


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else ".").resolve()
    strict, ratcheted, files = [], [], 0
    for top in STRICT + RATCHETED:
        for source in sorted((root / top).rglob("*")):
            if source.suffix not in (".cpp", ".hpp", ".h"):
                continue
            files += 1
            relative = source.relative_to(root).as_posix()
            for f in long_functions(source, relative):
                (strict if top in STRICT else ratcheted).append(f)
    for path, line, name, body in strict + sorted(ratcheted, key=lambda f: -f[3]):
        print(f"{path}:{line}: {name} ({body} lines) is longer than {LIMIT} lines")
    print(f"check_function_length: {len(strict)} in {', '.join(STRICT)} (allowed 0); "
          f"{len(ratcheted)} in {', '.join(RATCHETED)} (allowed {HOST_SIM_ALLOWED}); "
          f"{files} files of {root}")
    if files == 0:
        print("check_function_length: no C++ file under " + ", ".join(STRICT + RATCHETED))
        return 1
    return 1 if strict or len(ratcheted) > HOST_SIM_ALLOWED else 0


if __name__ == "__main__":
    sys.exit(main())
