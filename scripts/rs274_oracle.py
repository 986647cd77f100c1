#!/usr/bin/env python3
"""LinuxCNC's RS274NGC interpreter as an independent reader of a G-code file (issue 11 item 5).

    python3 scripts/rs274_oracle.py FILE     # one line per motion the interpreter reports
    python3 scripts/rs274_oracle.py --probe  # exit 0 when LinuxCNC's `gcode` module imports

The module comes from Debian's linuxcnc-uspace package, extracted (not installed) by
`scripts/setup.sh rs274` into WARPSLICE_RS274_ROOT (default ~/.cache/warpslice/rs274/root);
this script puts that folder's Python and library paths in front and re-executes itself.

FILE must already be what the interpreter reads (the caller maps the extruder to a spare axis
letter and blanks the M-codes it does not know, keeping one line per input line). Each motion is
printed as

    <line> <feed|traverse> <inverse|perminute> <rate> X Y Z A B C U V W

with linear axes in mm and rotary axes in degrees (the interpreter reports inches internally:
multiplied by 25.4 here) and the rate as the F the file gave (mm/min, or 1/min in inverse
time). A file the interpreter refuses prints `error <line> <message>` and exits 1.
"""

import os
import sys
import tempfile

ROOT = os.environ.get(
    "WARPSLICE_RS274_ROOT",
    os.path.join(os.path.expanduser("~"), ".cache", "warpslice", "rs274", "root"),
)
PY = os.path.join(ROOT, "usr", "lib", "python3", "dist-packages")
LIBS = [os.path.join(ROOT, "usr", "lib", "x86_64-linux-gnu"), os.path.join(ROOT, "usr", "lib")]

if os.environ.get("_WARPSLICE_RS274_ENV") != "1":
    env = dict(os.environ)
    env["_WARPSLICE_RS274_ENV"] = "1"
    env["PYTHONPATH"] = os.pathsep.join([PY] + [p for p in [env.get("PYTHONPATH")] if p])
    env["LD_LIBRARY_PATH"] = os.pathsep.join(LIBS + [p for p in [env.get("LD_LIBRARY_PATH")] if p])
    os.execve(sys.executable, [sys.executable] + sys.argv, env)

try:
    import gcode  # noqa: E402  (LinuxCNC's RS274NGC interpreter)
except ImportError as e:
    print(f"no LinuxCNC gcode module under {ROOT}: {e}", file=sys.stderr)
    sys.exit(2)

if sys.argv[1:] == ["--probe"]:
    sys.exit(0)

INCH = 25.4
LINEAR = [True, True, True, False, False, False, True, True, True]  # X Y Z A B C U V W


class Canon:
    """Records every motion; answers the interpreter's questions: millimetres in, every axis
    of XYZABCUVW present, no block delete, no tools, a writable parameter file."""

    def __init__(self):
        fd, self.parameter_file = tempfile.mkstemp(suffix=".var")
        os.close(fd)
        self.line = 0
        self.rate = 0.0
        self.inverse = False
        self.out = []

    def next_line(self, linecode):
        self.line = linecode.sequence_number

    def get_external_length_units(self):
        return 1.0 / INCH

    def get_external_angular_units(self):
        return 1.0

    def get_axis_mask(self):
        return 0x1FF

    def get_block_delete(self):
        return False

    def check_abort(self):
        return False

    def get_tool(self, pocket):
        return (-1,) + (0.0,) * 12 + (0,)

    def comment(self, text):
        if text.startswith("interpreter: feed mode set to"):
            self.inverse = "inverse time" in text

    def set_feed_rate(self, rate):
        self.rate = rate * INCH

    def _motion(self, kind, axes):
        vals = [v * INCH if lin else v for v, lin in zip(axes, LINEAR)]
        mode = "inverse" if self.inverse else "perminute"
        self.out.append(
            f"{self.line} {kind} {mode} {self.rate:.9g} " + " ".join(f"{v:.6f}" for v in vals)
        )

    def straight_feed(self, *axes):
        self._motion("feed", axes)

    def straight_traverse(self, *axes):
        self._motion("traverse", axes)

    def arc_feed(self, *args):
        self.out.append(f"{self.line} arc")

    def __getattr__(self, name):
        if name.startswith("_"):
            raise AttributeError(name)
        return lambda *args: None


def main(path):
    canon = Canon()
    try:
        result, seq = gcode.parse(path, canon, "G21", "G90 G94 G17")
    finally:
        os.unlink(canon.parameter_file)
    sys.stdout.write("\n".join(canon.out) + ("\n" if canon.out else ""))
    if result > gcode.MIN_ERROR:
        print(f"error {seq} {gcode.strerror(result)}")
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1]))
