#!/usr/bin/env python3
"""The facts of two run.json files, wherever each records them (the run-record check).

    compare_run_facts.py BEFORE/run.json AFTER/run.json

Every leaf value of BEFORE (a string or number; the files' checksums, the host's, the dates,
the run's seconds and the timings aside) must appear somewhere in AFTER: a fact may move (the
GL facts moved from run.json's top level into the glsl backend's block), never vanish. Prints
the keys only in BEFORE, only in AFTER, and the values lost; exit 1 when any value is lost."""
import json
import sys

VOLATILE = ("/files", "/date_utc", "/seconds", "/host", "/pid", "/command_line", "/git_",
            "/pxh_version", "/load", "/memory")


def leaves(j, path=""):
    if isinstance(j, dict):
        for k, v in j.items():
            yield from leaves(v, path + "/" + k)
    elif isinstance(j, list):
        for i, v in enumerate(j):
            yield from leaves(v, path + "/" + str(i))
    else:
        yield path, j


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    a = dict(leaves(json.load(open(sys.argv[1]))))
    b = dict(leaves(json.load(open(sys.argv[2]))))
    b_values = {json.dumps(v) for v in b.values()}
    only_a = sorted(k for k in a if k not in b)
    only_b = sorted(k for k in b if k not in a)
    lost = [k for k in only_a
            if not k.startswith(VOLATILE) and json.dumps(a[k]) not in b_values]
    print("keys only in BEFORE:", len(only_a), only_a[:20])
    print("keys only in AFTER:", len(only_b), only_b[:20])
    print("values lost:", len(lost), [(k, a[k]) for k in lost[:20]])
    sys.exit(1 if lost else 0)


if __name__ == "__main__":
    main()
