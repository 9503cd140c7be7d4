#!/usr/bin/python3
"""Canonical motions of an NC program from LinuxCNC's own interpreter, at full precision.

LinuxCNC's standalone rs274 prints positions with four decimals (0.1 um in mm, 2.5 um in inch
programs). This runs the same interpreter library through its Python binding (the one AXIS uses
for its preview), which hands over doubles, and prints the motions in rs274's text format with
every digit, in mm. Like rs274, the machine is an inch machine (the .var file is in inches).

usage: lcnc_canon.py PROGRAM.ngc PARAMETERS.var   (canonical lines on stdout; exit 1 on an
interpreter error, with LinuxCNC's message on stderr)
"""
import re
import sys

import gcode

MM = 25.4  # the binding reports lengths in inches


def mm(value):
    return repr(float(value) * MM)


class Canon:
    def __init__(self, program, parameter_file):
        self.parameter_file = parameter_file
        self.count = 0
        self.plane = "XY"
        self.line = 0
        with open(program) as f:
            self.lines = f.read().split("\n")

    def next_line(self, linecode):
        self.line = linecode.sequence_number  # 1-based line of the file

    def out(self, name, *args):
        # The N word of the line being executed, as rs274 prints it ("N....." without one).
        text = self.lines[self.line - 1] if 0 < self.line <= len(self.lines) else ""
        n = re.match(r"\s*[nN](\d+)", text)
        self.count += 1
        print("%5d %s %s(%s)" % (self.count, ("N" + n.group(1)).ljust(6) if n else "N.....",
                                  name, ", ".join(args)))

    def __getattr__(self, name):
        # Canonical calls without a geometric meaning (spindle, coolant, feed, next_line...).
        if name.startswith("__"):
            raise AttributeError(name)
        return lambda *args: None

    # What the interpreter asks about the machine.
    def get_external_length_units(self):
        return 0.03937007874016

    def get_external_angular_units(self):
        return 1.0

    def get_axis_mask(self):
        return 7

    def get_block_delete(self):
        return False

    def get_tool(self, pocket):
        return (-1,) + (0.0,) * 12 + (0,)

    def check_abort(self):
        return False

    # What it tells about the motion.
    def set_g5x_offset(self, index, x, y, z, *rest):
        self.out("SET_G5X_OFFSET", str(index), mm(x), mm(y), mm(z))

    def set_g92_offset(self, x, y, z, *rest):
        self.out("SET_G92_OFFSET", mm(x), mm(y), mm(z))

    def set_xy_rotation(self, degrees):
        if degrees != 0.0:
            sys.exit("lcnc_canon.py: coordinate system rotation is not handled here")

    def tool_offset(self, x, y, z, *rest):
        self.out("USE_TOOL_LENGTH_OFFSET", "%s %s %s" % (mm(x), mm(y), mm(z)))

    def set_plane(self, plane):
        self.plane = {1: "XY", 2: "YZ", 3: "XZ"}.get(plane, "XY")
        self.out("SELECT_PLANE", "CANON_PLANE_" + self.plane)

    def comment(self, text):
        self.out("COMMENT", '"%s"' % text)

    def straight_traverse(self, x, y, z, *rest):
        self.out("STRAIGHT_TRAVERSE", mm(x), mm(y), mm(z))

    def straight_feed(self, x, y, z, *rest):
        self.out("STRAIGHT_FEED", mm(x), mm(y), mm(z))

    def arc_feed(self, first_end, second_end, first_axis, second_axis, rotation, axis_end, *rest):
        self.out("ARC_FEED", mm(first_end), mm(second_end), mm(first_axis), mm(second_axis),
                 str(rotation), mm(axis_end))


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    canon = Canon(sys.argv[1], sys.argv[2])
    print("%5d N..... USE_LENGTH_UNITS(CANON_UNITS_MM)" % 0)
    result, sequence = gcode.parse(sys.argv[1], canon, "", "")
    if result > gcode.MIN_ERROR:
        sys.stderr.write("lcnc_canon.py: %s at line %d\n" % (gcode.strerror(result), sequence))
        sys.exit(1)


if __name__ == "__main__":
    main()
