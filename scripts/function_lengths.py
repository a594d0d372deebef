#!/usr/bin/env python3
"""Lists the longest C++ function bodies under the given folders (default: libs/).

  scripts/function_lengths.py [--top N] [--rev GIT_REV] [DIR ...]

A brace-counting scanner, not a compiler: comments, string and character literals are
blanked, then every '{' whose enclosing block is a namespace, a class or the file (not
a function) and whose header holds a parameter list ')' opens a function; its length is
the number of lines from the header's first line to the closing '}'. Lambdas and local
classes count towards the function that holds them. --rev reads the files as they were
at a git revision (git show), to compare before and after a change.
"""
import argparse
import re
import subprocess
import sys
from pathlib import Path

KEYWORDS_NOT_FUNCTIONS = re.compile(r"^\s*(namespace|class|struct|union|enum|extern)\b")
CONTROL = re.compile(r"^\s*(if|for|while|switch|catch|do|else|try)\b")


def blank_comments_and_literals(text):
    """Same length and line breaks, with comments and literals replaced by spaces."""
    pattern = re.compile(r'//[^\n]*|/\*.*?\*/|"(?:\\.|[^"\\\n])*"|\'(?:\\.|[^\'\\\n])*\'', re.S)
    return pattern.sub(lambda m: re.sub(r"[^\n]", " ", m.group(0)), text)


def functions(text):
    """(first line, last line, name) of every function definition."""
    code = blank_comments_and_literals(text)
    stack = []            # kind of each open block: "scope" or "function" or "other"
    header_start = 0      # offset where the current statement header starts
    found = []
    for i, ch in enumerate(code):
        if ch == "{":
            header = code[header_start:i]
            inside_function = any(kind[0] == "function" for kind in stack)
            if inside_function:
                stack.append(("other", i))
            elif KEYWORDS_NOT_FUNCTIONS.match(header.strip() and header.strip().splitlines()[-1] or "") \
                    or re.search(r"\b(namespace|class|struct|union|enum)\b[^()]*$", header):
                stack.append(("scope", i))
            elif ")" in header and not CONTROL.match(header) and not header.rstrip().endswith("="):
                name = re.findall(r"([~\w:]+(?:operator\s*\S+)?)\s*\(", header)
                stack.append(("function", header_start + len(header) - len(header.lstrip()),
                              name[0] if name else "?"))
            else:
                stack.append(("other", i))
            header_start = i + 1
        elif ch == "}":
            if stack:
                block = stack.pop()
                if block[0] == "function":
                    first = code.count("\n", 0, block[1]) + 1
                    last = code.count("\n", 0, i) + 1
                    found.append((first, last, block[2]))
            header_start = i + 1
        elif ch == ";":
            header_start = i + 1
        elif ch == "#" and (i == 0 or code[i - 1] == "\n"):
            header_start = code.find("\n", i) + 1 or len(code)  # preprocessor line
    return found


def sources(dirs, rev):
    if rev:
        listing = subprocess.run(["git", "ls-tree", "-r", "--name-only", rev, "--", *dirs],
                                 check=True, capture_output=True, text=True).stdout.split()
        for path in listing:
            if path.endswith((".cpp", ".h")):
                yield path, subprocess.run(["git", "show", f"{rev}:{path}"], check=True,
                                           capture_output=True, text=True).stdout
    else:
        for d in dirs:
            for path in sorted(Path(d).rglob("*")):
                if path.suffix in (".cpp", ".h"):
                    yield str(path), path.read_text(encoding="utf-8")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--top", type=int, default=10)
    parser.add_argument("--rev")
    parser.add_argument("dirs", nargs="*", default=["libs"])
    args = parser.parse_args()
    rows = []
    for path, text in sources(args.dirs, args.rev):
        for first, last, name in functions(text):
            rows.append((last - first + 1, f"{path}:{first}", name))
    rows.sort(key=lambda r: (-r[0], r[1]))
    for length, where, name in rows[:args.top]:
        print(f"{length:5d}  {where}  {name}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
