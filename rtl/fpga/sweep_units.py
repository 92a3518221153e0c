#!/usr/bin/env python3
"""sweep_units.py — the design-space view's units (docs/fpga.md, make fpga-sweep):
each RTL unit with the parameters alb_vp gives it, from the profile's fields.

  sweep_units.py --list                       the units, one a line
  sweep_units.py UNIT NAME=VALUE ...           yosys -chparam options for UNIT

NAME=VALUE are the profile as rtl/profile-params.sh --format shell prints it
(WIDTH=512 ...).  The derivations are alb_vp's (rtl/alb_vp.sv): LW, LH, EW,
and the defaults of the parameters the profile does not bound (MAX_EDGES,
TEX_WORDS, TEX_IDS, SCAN_PIXELS, TAG_BITS, ZR_REG, and the units SHADE_UNIT,
TEX_UNIT, FOG_UNIT: all built); tests/fpga-sweep.sh holds
them against alb_vp elaborated by yosys.
"""
import sys

# unit -> (source files, extra files it instantiates)
UNITS = {
    "alb_fifo": ["rtl/alb_fifo.sv"],
    "alb_parser": ["rtl/alb_parser.sv"],
    "alb_edge_store": ["rtl/alb_edge_store.sv"],
    "alb_engine": ["rtl/alb_engine.sv"],
    "alb_fill_queue": ["rtl/alb_fill_queue.sv"],
    "alb_fill": ["rtl/alb_fill.sv"],
    "alb_pipe": ["rtl/alb_pipe.sv", "rtl/alb_pipe_reg.sv"],
    "alb_frame_store": ["rtl/alb_frame_store.sv"],
    "alb_frame_crc": ["rtl/alb_frame_crc.sv"],
}
# alb_vp's defaults for what the profile does not bound
RTL_DEFAULTS = {"MAX_EDGES": 64, "TEX_WORDS": 65536, "TEX_IDS": 256, "SCAN_PIXELS": 1,
                "TAG_BITS": 8, "ZR_REG": 0, "SHADE_UNIT": 1, "TEX_UNIT": 1, "FOG_UNIT": 1}


def clog2(n):
    return (n - 1).bit_length()


def unit_params(unit, p):
    """The parameters alb_vp passes UNIT (rtl/alb_vp.sv's instances)."""
    q = dict(RTL_DEFAULTS)
    q.update(p)
    lw = clog2(q["WIDTH"]) + q["AA"]
    lh = clog2(q["HEIGHT"]) + q["AA"]
    ew = q["EDGE_FRAC_BITS"] + max(lw, lh) + 7
    table = {
        "alb_fifo": {"DEPTH": q["FIFO_DEPTH"]},
        "alb_parser": {"F": q["EDGE_FRAC_BITS"], "CB": q["COEF_BITS"], "COLB": q["COLOUR_BITS"],
                       "LW": lw, "LH": lh, "EW": ew, "MAX_EDGES": q["MAX_EDGES"],
                       "TEX_WORDS": q["TEX_WORDS"], "TEX_IDS": q["TEX_IDS"],
                       "FRAME_FACES": q["FRAME_FACES"], "SHADE_UNIT": q["SHADE_UNIT"],
                       "TEX_UNIT": q["TEX_UNIT"], "FOG_UNIT": q["FOG_UNIT"]},
        "alb_edge_store": {"FACE_SLOTS": q["FACE_SLOTS"], "MAX_EDGES": q["MAX_EDGES"],
                           "EW": ew, "LANES": q["EDGE_UNITS"]},
        "alb_engine": {"LW": lw, "LH": lh, "EW": ew, "MAX_EDGES": q["MAX_EDGES"],
                       "E": q["EDGE_UNITS"]},
        "alb_fill_queue": {"DEPTH": q["FILL_QUEUE"]},
        "alb_fill": {"RATE": q["FILL_RATE"], "LW": lw, "LH": lh},
        "alb_pipe": {"RATE": q["FILL_RATE"], "LW": lw, "LH": lh, "CB": q["COEF_BITS"],
                     "DB": q["DEPTH_BITS"], "COLB": q["COLOUR_BITS"], "RB": q["RECIP_BITS"],
                     "FI": q["SHADE_FRAC_BITS"], "DIV_LAT": q["DIVIDER_LATENCY"],
                     "SHADE_LAT": q["SHADE_LATENCY"], "TEX_WORDS": q["TEX_WORDS"],
                     "ZR_REG": q["ZR_REG"], "SHADE_UNIT": q["SHADE_UNIT"],
                     "TEX_UNIT": q["TEX_UNIT"], "FOG_UNIT": q["FOG_UNIT"]},
        "alb_frame_store": {"RATE": q["FILL_RATE"], "LW": lw, "LH": lh, "AA": q["AA"],
                            "DB": q["DEPTH_BITS"], "COLB": q["COLOUR_BITS"],
                            "TAG_BITS": q["TAG_BITS"], "FRAME_QUEUE": q["FRAME_QUEUE"]},
        "alb_frame_crc": {"LW": lw, "LH": lh, "AA": q["AA"], "COLB": q["COLOUR_BITS"],
                          "TAG_BITS": q["TAG_BITS"], "PIXELS": q["SCAN_PIXELS"]},
    }
    return table[unit]


def main(argv):
    if argv[1:] == ["--list"]:
        print("\n".join(UNITS))
        return 0
    if len(argv) < 2 or argv[1] not in UNITS:
        sys.stderr.write("usage: sweep_units.py --list | UNIT NAME=VALUE ... (units: %s)\n"
                         % " ".join(UNITS))
        return 2
    p = {}
    for kv in argv[2:]:
        name, sep, value = kv.partition("=")
        if not sep or not value.lstrip("-").isdigit():
            sys.stderr.write("sweep_units.py: %r: expected NAME=INTEGER\n" % kv)
            return 2
        p[name] = int(value)
    try:
        params = unit_params(argv[1], p)
    except KeyError as e:
        sys.stderr.write("sweep_units.py: the profile has no %s\n" % e)
        return 2
    print(" ".join("-chparam %s %d" % kv for kv in sorted(params.items())))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
