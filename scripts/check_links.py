#!/usr/bin/python3
"""Checks the documentation's links: every relative link and image in README.md,
CONTRIBUTING.md and docs/**/*.md must name a file or folder of the repository, and a
`#fragment` must name a heading of the file it points into (GitHub's slugs: lower case,
punctuation but `-` and `_` dropped, spaces to `-`, repeats numbered -1, -2, ...). README.md
may have at most 400 lines. Links to web addresses (http:, https:, mailto:) are not checked.

Usage: check_links.py [REPOSITORY_ROOT]   (default: the folder above this script)
       check_links.py --selftest          (the checker finds the problems of a broken tree)
Prints one line per problem, FILE:LINE: problem, and exits 1 if there is any, else 0.
"""
import os
import re
import sys

README_MAX_LINES = 400

# [text](target) and ![alt](target), the target up to the first space or ')' (an optional
# "title" after it); <a href="..."> and <img src="..."> in inline HTML.
MD_LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")
HTML_LINK = re.compile(r"<(?:a|img)\s[^>]*?(?:href|src)=\"([^\"]+)\"", re.IGNORECASE)
REF_DEF = re.compile(r"^\s{0,3}\[[^\]]+\]:\s*<?(\S+?)>?(?:\s|$)")
FENCE = re.compile(r"^\s{0,3}(```|~~~)")


def slug(heading):
    """GitHub's anchor for a heading's text."""
    text = re.sub(r"<[^>]+>", "", heading)  # inline HTML
    text = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", text)  # links keep their text
    text = text.strip().lower()
    text = re.sub(r"[^\w\- ]", "", text)  # punctuation (incl. `, *, ., :, ...) dropped
    return text.replace(" ", "-")


def anchors(path, cache={}):
    if path not in cache:
        seen = {}
        result = set()
        in_fence = False
        with open(path, encoding="utf-8") as f:
            for line in f:
                if FENCE.match(line):
                    in_fence = not in_fence
                    continue
                if in_fence:
                    continue
                m = re.match(r"^\s{0,3}(#{1,6})\s+(.*?)\s*#*\s*$", line)
                if not m:
                    continue
                s = slug(m.group(2))
                n = seen.get(s, 0)
                seen[s] = n + 1
                result.add(s if n == 0 else f"{s}-{n}")
                for a in re.findall(r"<a\s+(?:name|id)=\"([^\"]+)\"", line):
                    result.add(a)
        cache[path] = result
    return cache[path]


def links(path):
    """(line number, target) for every link outside code fences and inline code."""
    in_fence = False
    with open(path, encoding="utf-8") as f:
        for number, line in enumerate(f, 1):
            if FENCE.match(line):
                in_fence = not in_fence
                continue
            if in_fence:
                continue
            text = re.sub(r"``[^`]*``|`[^`]*`", "", line)
            for regex in (MD_LINK, HTML_LINK, REF_DEF):
                for m in regex.finditer(text):
                    yield number, m.group(1)


def check(root):
    problems = []
    files = [os.path.join(root, "README.md"), os.path.join(root, "CONTRIBUTING.md")]
    for folder, _, names in os.walk(os.path.join(root, "docs")):
        files += [os.path.join(folder, n) for n in sorted(names) if n.endswith(".md")]
    for path in files:
        if not os.path.isfile(path):
            problems.append(f"{os.path.relpath(path, root)}: missing")
            continue
        rel = os.path.relpath(path, root)
        for number, target in links(path):
            if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target):  # http:, https:, mailto:
                continue
            file_part, _, fragment = target.partition("#")
            dest = path if not file_part else os.path.normpath(
                os.path.join(os.path.dirname(path), file_part))
            if not os.path.exists(dest):
                problems.append(f"{rel}:{number}: {target}: no such file")
                continue
            if not os.path.realpath(dest).startswith(os.path.realpath(root) + os.sep):
                problems.append(f"{rel}:{number}: {target}: outside the repository")
                continue
            if fragment and dest.endswith(".md"):
                if fragment not in anchors(dest):
                    problems.append(f"{rel}:{number}: {target}: no heading "
                                    f"'#{fragment}' in {os.path.relpath(dest, root)}")
    readme = os.path.join(root, "README.md")
    if os.path.isfile(readme):
        with open(readme, encoding="utf-8") as f:
            count = sum(1 for _ in f)
        if count > README_MAX_LINES:
            problems.append(f"README.md:{count}: {count} lines, more than {README_MAX_LINES}")
    return problems


def selftest():
    """A tree with one problem of each kind, and the same links mended: the checker must name
    exactly the problems planted."""
    import tempfile
    with tempfile.TemporaryDirectory() as root:
        os.makedirs(os.path.join(root, "docs", "guide"))
        def write(rel, text):
            with open(os.path.join(root, rel), "w", encoding="utf-8") as f:
                f.write(text)
        write("CONTRIBUTING.md", "# Contributing\n")
        write("docs/guide/a.md", "# A\n\n## Two words: `code`\n\n## Two words: `code`\n\n"
              "[up](../../README.md#pxh) [self](#two-words-code-1) [web](https://example.org/x)\n"
              "```\n[in a fence](nowhere.md)\n```\n")
        good = "# pxh\n\n[a](docs/guide/a.md#two-words-code) ![f](docs/guide/a.md)\n"
        write("README.md", good)
        if check(root):
            print("selftest: a sound tree reported problems:", check(root))
            return 1
        write("README.md", good + "[b](docs/missing.md) [c](docs/guide/a.md#no-such)\n"
              + "<img src=\"docs/none.png\">\n" + "x\n" * 400)
        found = check(root)
        expected = ["README.md:4: docs/missing.md: no such file",
                    "README.md:4: docs/guide/a.md#no-such: no heading '#no-such' in docs/guide/a.md",
                    "README.md:5: docs/none.png: no such file",
                    "README.md:405: 405 lines, more than 400"]
        if found != expected:
            print("selftest: expected", expected, "found", found)
            return 1
    print("selftest: ok")
    return 0


def main():
    if sys.argv[1:] == ["--selftest"]:
        return selftest()
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(
        os.path.abspath(__file__)), os.pardir)
    root = os.path.abspath(root)
    problems = check(root)
    for p in problems:
        print(p)
    if problems:
        print(f"check_links: {len(problems)} problem(s)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
