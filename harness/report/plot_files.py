"""pxh report's plot script (plot_report.py): its files created new in the folder it draws into,
paths inside the results folder with no link on the way, and the data files read."""
import csv
import math
import os
import sys


def fail(msg, status=2):
    print("pxh: error: " + msg.replace("\n", "\\n"), file=sys.stderr)
    sys.exit(status)


class NewFiles:
    """Creates files in one folder, each a new name (O_CREAT | O_EXCL | O_NOFOLLOW: never over
    what exists, never through a link). pxh report gives the script a staging folder of its own
    (--into) and takes the files into the report folder after the script ends
    (harness/core/safe_files.h: OwnedFolder::adopt): what is safe there is decided there."""

    def __init__(self, into):
        if os.path.islink(into) or not os.path.isdir(into):
            fail(f"{into}: not a folder (or a symbolic link); the figures go into a folder")
        self.into = into

    def write(self, name, writer):
        """writer(binary file) writes the contents; a file that fails half-way is removed."""
        path = os.path.join(self.into, name)
        try:
            fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
        except FileExistsError:
            fail(f"{path}: exists; the plot script writes only new files (name an empty "
                 "folder with --into)")
        try:
            with os.fdopen(fd, "wb") as f:
                writer(f)
        except BaseException:
            os.unlink(path)
            raise
        return path


def inside(results, rel, what):
    """RESULTS/rel, refused (exit 2) unless rel is relative, without '..' and with no link on
    the way."""
    if os.path.isabs(rel) or ".." in rel.split("/"):
        fail(f"{what}: '{rel}' lies outside the results folder {results}; refused")
    at = results
    for part in rel.split("/"):
        at = os.path.join(at, part)
        if os.path.islink(at):
            fail(f"{what}: '{rel}' passes through a symbolic link ({at}); refused")
    return os.path.join(results, rel)


def read(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def num(s):
    try:
        v = float(s)
        return v if math.isfinite(v) else None
    except (TypeError, ValueError):
        return None


def safe(name):
    return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)
