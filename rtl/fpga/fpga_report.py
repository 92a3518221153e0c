#!/usr/bin/env python3
"""fpga_report.py REPORT.json --clock NET=MHZ [--clock NET=MHZ ...] [--json]

Judge nextpnr-ice40's --report JSON (docs/fpga.md): the design fits when every
resource's "used" is at most its "available", and meets its clocks when each
named clock's achieved Fmax is at least the MHz given.  Prints one line per
resource and clock and a verdict; exits 0 if both hold, 1 if not, 2 if the
report cannot be read or lacks what is asked for (named with the file and the
key).  A clock NET matches a "fmax" entry whose name is NET or ends in
"$NET" or "NET_..." (nextpnr names a clock by its net)."""
import json
import sys


def fail_input(msg):
    print(f"fpga_report.py: {msg}", file=sys.stderr)
    sys.exit(2)


def find_clock(fmax, net):
    for name in fmax:
        if name == net or name.endswith("$" + net) or name.startswith(net + "_") \
                or name.startswith(net + "$"):
            return name
    return None


def main(argv):
    path, clocks, as_json = None, [], False
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--clock" and i + 1 < len(argv):
            net, eq, mhz = argv[i + 1].partition("=")
            try:
                clocks.append((net, float(mhz)))
            except ValueError:
                eq = ""
            if not eq or not net:
                fail_input(f"--clock {argv[i + 1]}: expected NET=MHZ")
            i += 2
        elif a == "--json":
            as_json = True
            i += 1
        elif a.startswith("-") or path:
            fail_input("usage: fpga_report.py REPORT.json --clock NET=MHZ ... [--json]")
        else:
            path = a
            i += 1
    if not path:
        fail_input("usage: fpga_report.py REPORT.json --clock NET=MHZ ... [--json]")
    try:
        with open(path, encoding="utf-8") as f:
            rep = json.load(f)
    except OSError as e:
        fail_input(f"{path}: {e.strerror}")
    except json.JSONDecodeError as e:
        fail_input(f"{path}: line {e.lineno} column {e.colno}: not JSON: {e.msg}")
    if not isinstance(rep, dict):
        fail_input(f"{path}: expected an object at the top")
    util = rep.get("utilization")
    fmax = rep.get("fmax")
    if not isinstance(util, dict) or not util:
        fail_input(f"{path}: no 'utilization' object (nextpnr --report writes one)")
    if not isinstance(fmax, dict):
        fail_input(f"{path}: no 'fmax' object (nextpnr --report writes one)")

    ok = True
    out = {"resources": {}, "clocks": {}}
    for res in sorted(util):
        u = util[res]
        try:
            used, avail = int(u["used"]), int(u["available"])
        except (TypeError, KeyError, ValueError):
            fail_input(f"{path}: utilization.{res}: expected 'used' and 'available' integers")
        fits = used <= avail
        ok &= fits
        out["resources"][res] = {"used": used, "available": avail, "fits": fits}
        pct = 100.0 * used / avail if avail else (0.0 if used == 0 else float("inf"))
        if not as_json:
            print(f"{'ok  ' if fits else 'OVER'} {res:<14} {used:>6} / {avail:<6} {pct:6.1f}%")
    for net, want in clocks:
        name = find_clock(fmax, net)
        if name is None and not fmax and not ok:
            # nextpnr --pack-only: the design was not placed, being too big
            out["clocks"][net] = {"net": None, "required_mhz": want, "meets": False}
            if not as_json:
                print(f"SLOW clock {net:<8} no Fmax: not placed (it does not fit)")
            continue
        if name is None:
            fail_input(f"{path}: fmax has no clock '{net}' (it has: {', '.join(sorted(fmax)) or 'none'})")
        try:
            got = float(fmax[name]["achieved"])
        except (TypeError, KeyError, ValueError):
            fail_input(f"{path}: fmax.{name}: expected an 'achieved' number")
        meets = got >= want
        ok &= meets
        out["clocks"][net] = {"net": name, "achieved_mhz": got, "required_mhz": want, "meets": meets}
        if not as_json:
            print(f"{'ok  ' if meets else 'SLOW'} clock {net:<8} Fmax {got:8.2f} MHz, needs {want:.2f} MHz"
                  f" ({got / want:.2f}x)")
    out["fits_and_meets"] = ok
    if as_json:
        print(json.dumps(out, indent=1, sort_keys=True))
    else:
        print("fits and meets its clocks" if ok else "does NOT fit or meet its clocks")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
