#!/usr/bin/python3
"""Sizes the house rules limit (files under 600 lines, functions under 120): lists every C++
source file over --file-lines and every function body over --function-lines.

Functions are found by their braces: a line ending in "{" whose text looks like a function
head (a parameter list, no control keyword), its body up to the matching brace. Strings,
characters and comments are skipped when counting braces. Lambdas inside a function count
towards it. Usage: scripts/code_sizes.py [--file-lines 600] [--function-lines 120] [PATH ...]
(default: the files git tracks). Exit status 1 when something is over, 0 otherwise.
"""
import argparse
import re
import subprocess
import sys

CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|try|return)\b")
HEAD = re.compile(r"\)\s*(const\s*)?(noexcept\s*)?(override\s*)?(final\s*)?(->\s*[\w:<>,\s*&]+)?\s*\{\s*$")


def strip_code(text):
    """The text with strings, characters and comments blanked (newlines kept)."""
    out, i, n = [], 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i)); i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j])); i = j
        elif text.startswith('R"', i):
            m = re.match(r'R"([^(]*)\(', text[i:])
            end = text.find(")" + m.group(1) + '"', i) if m else -1
            j = n if end < 0 else end + len(m.group(1)) + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j])); i = j
        elif c in "\"'":
            j = i + 1
            while j < n and text[j] != c:
                j += 2 if text[j] == "\\" else 1
            out.append(" " * (j + 1 - i)); i = j + 1
        else:
            out.append(c); i += 1
    return "".join(out)


def functions(path):
    lines = strip_code(open(path, encoding="utf-8", errors="replace").read()).split("\n")
    found, i = [], 0
    while i < len(lines):
        line = lines[i]
        if HEAD.search(line) and not CONTROL.match(line) and "=" not in line.split("(")[0]:
            depth, j = 0, i
            while j < len(lines):
                depth += lines[j].count("{") - lines[j].count("}")
                if depth <= 0 and j > i or (depth == 0 and j == i and "}" in lines[j]):
                    break
                j += 1
            found.append((i + 1, j - i + 1, line.strip()))
            i = j + 1 if j > i else i + 1
            continue
        i += 1
    return found


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--file-lines", type=int, default=600)
    parser.add_argument("--function-lines", type=int, default=120)
    parser.add_argument("paths", nargs="*")
    args = parser.parse_args()
    paths = args.paths or subprocess.run(
        ["git", "ls-files", "*.cpp", "*.hpp"], capture_output=True, text=True, check=True
    ).stdout.split()
    over = 0
    for path in paths:
        count = sum(1 for _ in open(path, encoding="utf-8", errors="replace"))
        if count > args.file_lines:
            print(f"{path}: {count} lines (file)")
            over += 1
        for line, length, head in functions(path):
            if length > args.function_lines:
                print(f"{path}:{line}: {length} lines: {head[:90]}")
                over += 1
    print(f"{over} over the limits (files > {args.file_lines} lines, functions > "
          f"{args.function_lines} lines)", file=sys.stderr)
    return 1 if over else 0


if __name__ == "__main__":
    sys.exit(main())
