"""pxh report's plot script (plot_report.py): the report folder's files written as pxh report
writes them (through a temporary name, never over a file that is not in the manifest), paths
inside the results folder with no link on the way, and the data files read."""
import csv
import errno
import math
import os
import sys


MANIFEST = "manifest.txt"


def fail(msg, status=2):
    print("pxh: error: " + msg.replace("\n", "\\n"), file=sys.stderr)
    sys.exit(status)


class Own:
    """The report folder's files as pxh report writes them (harness/report/report_data.h)."""

    def __init__(self, out):
        self.out = out
        self.manifest = os.path.join(out, MANIFEST)
        if os.path.islink(out):
            fail(f"{out}: is a symbolic link; pxh report writes only into a folder of its own")
        try:
            fd = os.open(self.manifest, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW,
                         0o644)
            os.write(fd, b"# The files pxh report wrote in this folder, one a line: the next "
                         b"pxh report removes exactly these, and nothing else.\n")
            os.close(fd)
        except FileExistsError:
            pass
        if os.path.islink(self.manifest) or not os.path.isfile(self.manifest):
            fail(f"{self.manifest}: is not a regular file (a link?), so not pxh report's list "
                 "of its files")
        with open(self.manifest, encoding="utf-8", errors="replace") as f:
            self.ours = {line.rstrip("\n") for line in f if not line.startswith("#")}

    def record(self, name):
        fd = os.open(self.manifest, os.O_WRONLY | os.O_APPEND | os.O_NOFOLLOW)
        try:
            os.write(fd, (name + "\n").encode("utf-8", "surrogateescape"))
        finally:
            os.close(fd)
        self.ours.add(name)

    def write(self, name, writer):
        """writer(binary file) writes the contents; then the file takes its name."""
        path = os.path.join(self.out, name)
        tmp_name = f".{name}.tmp-{os.getpid()}"
        tmp = os.path.join(self.out, tmp_name)
        fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
        self.record(tmp_name)
        try:
            with os.fdopen(fd, "wb") as f:
                writer(f)
        except BaseException:
            os.unlink(tmp)
            raise
        if name in self.ours and os.path.isfile(path) and not os.path.islink(path):
            os.unlink(path)  # ours, from an earlier drawing: replaced
        try:
            os.link(tmp, path)
        except FileExistsError:
            os.unlink(tmp)
            fail(f"{path}: exists and pxh report did not write it (it is not in "
                 f"{self.manifest}); move it away or remove it")
        except OSError as e:
            if e.errno not in (errno.EPERM, errno.ENOTSUP, errno.EXDEV, errno.EMLINK) or \
                    os.path.lexists(path):
                os.unlink(tmp)
                raise
            os.rename(tmp, path)  # a file system without hard links
        else:
            os.unlink(tmp)
        self.record(name)


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
