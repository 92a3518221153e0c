#!/usr/bin/env python3
"""sweep_collect.py DIR --units "U ..." --families "F ..." NAME:PROFILE[:k=v...] ...

The design-space view's CSV (docs/fpga.md, make fpga-sweep) from its jobs'
outputs in DIR: per point DIR/NAME/params (rtl/profile-params.sh --format
shell), DIR/NAME/UNIT.unit (rtl/fpga/sweep-unit.sh) and DIR/NAME/cycles
(rtl/fpga/sweep-cycles.sh).  One row a point: its parameters, cells per unit,
their total, memory bits, the synthesis's CPU seconds (all units), cycles per frame per scene.  A missing or
malformed job output is an error naming the file and line; no CSV then.
"""
import sys

PARAMS = ["WIDTH", "HEIGHT", "EDGE_UNITS", "FILL_RATE", "FACE_SLOTS", "FILL_QUEUE", "FIFO_DEPTH"]


class Bad(Exception):
    pass


def read_lines(path):
    try:
        with open(path) as f:
            lines = f.read().splitlines()
    except OSError as e:
        raise Bad("%s: %s (the job did not run or failed: make fpga-sweep)" % (path, e.strerror))
    if not lines:
        raise Bad("%s: empty" % path)
    return lines


def fields(path, line, lineno, need):
    """key=integer fields of one line, every key of need present."""
    out = {}
    for col, tok in enumerate(line.split(), 1):
        key, sep, value = tok.partition("=")
        if not sep or not key:
            raise Bad("%s:%d: field %d %r: expected key=value" % (path, lineno, col, tok))
        out[key] = value
    for key in need:
        if key not in out:
            raise Bad("%s:%d: no %s=" % (path, lineno, key))
        if not out[key].isdigit():
            raise Bad("%s:%d: %s=%r: expected a non-negative integer" % (path, lineno, key, out[key]))
    return out


def point_row(d, spec, units, families):
    parts = spec.split(":")
    if len(parts) < 2 or not parts[0] or not parts[1]:
        raise Bad("point %r: expected NAME:PROFILE[:key=value...]" % spec)
    name, profile, sets = parts[0], parts[1], parts[2:]
    base = "%s/%s" % (d, name)
    params = {}
    for n, line in enumerate(read_lines(base + "/params"), 1):
        params.update(fields(base + "/params", line, n, []))
    for key in PARAMS:
        if not params.get(key, "").isdigit():
            raise Bad("%s/params: no %s (an integer)" % (base, key))
    cells, mem, secs = [], 0, 0
    for u in units:
        path = "%s/%s.unit" % (base, u)
        lines = read_lines(path)
        if len(lines) != 1:
            raise Bad("%s: %d lines, expected one" % (path, len(lines)))
        f = fields(path, lines[0], 1, ["cells", "memory_bits", "memories", "cpu_seconds"])
        if f.get("unit") != u:
            raise Bad("%s:1: unit=%r, expected %s" % (path, f.get("unit"), u))
        cells.append(int(f["cells"]))
        mem += int(f["memory_bits"])
        secs += int(f["cpu_seconds"])
    path = base + "/cycles"
    lines = read_lines(path)
    if len(lines) != 1:
        raise Bad("%s: %d lines, expected one" % (path, len(lines)))
    c = fields(path, lines[0], 1, ["builtin"] + families)
    return ([name, profile, " ".join(sets)] + [params[k] for k in PARAMS] +
            [str(x) for x in cells] + [str(sum(cells)), str(mem), str(secs)] +
            [c["builtin"]] + [c[f] for f in families])


def main(argv):
    args = argv[1:]
    try:
        if len(args) < 6 or args[1] != "--units" or args[3] != "--families":
            raise Bad("usage: sweep_collect.py DIR --units \"U ...\" --families \"F ...\" POINT ...")
        d, units, families, points = args[0], args[2].split(), args[4].split(), args[5:]
        rows = [point_row(d, p, units, families) for p in points]
    except Bad as e:
        sys.stderr.write("sweep_collect.py: %s\n" % e)
        return 1
    head = (["point", "profile", "sets"] + [k.lower() for k in PARAMS] +
            ["cells_" + u.replace("alb_", "") for u in units] +
            ["cells_total", "memory_bits", "synth_cpu_seconds", "cycles_builtin"] +
            ["cycles_" + f for f in families])
    print(",".join(head))
    for r in rows:
        print(",".join(r))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
