#!/usr/bin/env python3
"""Lists every function longer than N lines (default 80) in C++ sources.

    scripts/long_functions.py [--max N] [PATH ...]   (default PATH: harness methods heightfields)

Prints FILE:LINE name length for each, longest first; exit status 0 either way (a report, not a
gate). A heuristic, not a parser: comments and string/char literals are blanked out, then a
function is a top-level brace block (outside any class, struct, enum or namespace body, but
inside namespaces) whose opening brace follows a ')' (optionally followed by const, noexcept,
override, a trailing return type or a constructor's initialiser list). Lambdas inside a
function count towards that function. Member functions defined inside a class body are found
too (a class body is searched like a namespace). Its length runs from the line of its name to
the line of its closing brace.
"""
import argparse
import os
import re
import sys

EXTS = (".cpp", ".cc", ".h", ".hpp")


def blank(text):
    """Comments, string and char literals replaced by spaces (newlines kept)."""
    out = []
    i, n = 0, len(text)
    while i < n:
        c = text[i]
        if text.startswith("//", i):
            j = text.find("\n", i)
            j = n if j < 0 else j
            out.append(" " * (j - i))
            i = j
        elif text.startswith("/*", i):
            j = text.find("*/", i + 2)
            j = n if j < 0 else j + 2
            out.append(re.sub(r"[^\n]", " ", text[i:j]))
            i = j
        elif c == 'R' and text.startswith('R"', i) and (i == 0 or not (text[i - 1].isalnum() or text[i - 1] == '_')):
            m = re.match(r'R"([^(\s]*)\(', text[i:])
            if m:
                end = text.find(")" + m.group(1) + '"', i)
                end = n if end < 0 else end + len(m.group(1)) + 2
                out.append(re.sub(r"[^\n]", " ", text[i:end]))
                i = end
            else:
                out.append(c)
                i += 1
        elif c in "\"'":
            if c == "'" and i > 0 and text[i - 1].isalnum():  # digit separator 1'000
                out.append(" ")
                i += 1
                continue
            j = i + 1
            while j < n and text[j] != c and text[j] != "\n":
                j += 2 if text[j] == "\\" else 1
            j = min(j + 1, n)
            out.append(" " * (j - i))
            i = j
        else:
            out.append(c)
            i += 1
    return "".join(out)


SCOPE_RE = re.compile(r"\b(namespace|class|struct|union|enum)\b[^;{}()]*$")
FUNC_TAIL_RE = re.compile(
    r"\)\s*(const\s*)?(noexcept(\([^()]*\))?\s*)?(override\s*|final\s*)*(->\s*[\w:<>,\s*&]+)?$")
NAME_RE = re.compile(r"([~\w:]+(?:<[^()]*>)?|operator\s*[^\s(]+)\s*\($")


def head_of(code, brace):
    """The text between the previous ';', '{' or '}' and this brace."""
    k = brace - 1
    while k >= 0 and code[k] not in ";{}":
        k -= 1
    return k + 1, code[k + 1:brace]


def function_name(head):
    """The name before the parameter list whose ')' closes the head, or None."""
    h = head.rstrip()
    # A constructor's initialiser list: cut at the ':' that follows the parameter list.
    depth = 0
    close = -1
    for idx, ch in enumerate(h):
        if ch == "(":
            depth += 1
        elif ch == ")":
            depth -= 1
            if depth == 0 and close < 0:
                close = idx
    if close < 0:
        return None
    tail = h[close:]
    if not (FUNC_TAIL_RE.match(tail.strip()) or re.match(r"\)\s*(noexcept\s*)?:", tail)):
        return None
    # Find the matching '(' of that first ')'.
    depth = 0
    for idx in range(close, -1, -1):
        if h[idx] == ")":
            depth += 1
        elif h[idx] == "(":
            depth -= 1
            if depth == 0:
                m = NAME_RE.search(h[:idx + 1])
                if not m:
                    return None
                name = m.group(1)
                if name in ("if", "for", "while", "switch", "catch", "return", "sizeof"):
                    return None
                return name
    return None


def scan(path, limit):
    text = open(path, encoding="utf-8", errors="replace").read()
    code = blank(text)
    line_of = [0] * (len(code) + 1)
    ln = 1
    for i, ch in enumerate(code):
        line_of[i] = ln
        if ch == "\n":
            ln += 1
    line_of[len(code)] = ln
    found = []
    # A stack of scopes: 'scope' (namespace/class body: functions may start here) or
    # ('func', name, start_line) or 'block'.
    stack = []
    for i, ch in enumerate(code):
        if ch == "{":
            in_function = any(isinstance(s, tuple) for s in stack)
            start, head = head_of(code, i)
            if in_function:
                stack.append("block")
            elif SCOPE_RE.search(head.strip()) or head.strip().startswith("extern"):
                stack.append("scope")
            else:
                name = function_name(head)
                if name:
                    first = start + len(head) - len(head.lstrip())
                    stack.append(("func", name, line_of[first]))
                else:
                    stack.append("block")
        elif ch == "}" and stack:
            top = stack.pop()
            if isinstance(top, tuple):
                length = line_of[i] - top[2] + 1
                if length > limit:
                    found.append((path, top[2], top[1], length))
    return found


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max", type=int, default=80, help="report functions longer than this")
    ap.add_argument("paths", nargs="*", default=["harness", "methods", "heightfields"])
    a = ap.parse_args()
    files = []
    for p in a.paths:
        if os.path.isdir(p):
            for root, _, names in os.walk(p):
                files += [os.path.join(root, f) for f in names if f.endswith(EXTS)]
        elif p.endswith(EXTS):
            files.append(p)
        else:
            print(f"long_functions.py: {p}: not a folder or C++ file", file=sys.stderr)
            return 2
    found = []
    for f in sorted(files):
        found += scan(f, a.max)
    for path, line, name, length in sorted(found, key=lambda x: -x[3]):
        print(f"{path}:{line} {name} {length}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
