#!/usr/bin/env python3
"""sweep_stat.py STAT.json MEM.json UNIT SECONDS CPU_SECONDS ABC — one line of the
design-space view (rtl/fpga/sweep-unit.sh): the flattened unit's cells from
yosys `stat -json`, its memories ($mem_v2 cells, from `write_json -selected`)
as bits (WIDTH x SIZE), not as cells."""
import json
import sys


def fail(msg):
    sys.stderr.write("sweep_stat.py: %s\n" % msg)
    sys.exit(1)


def main(argv):
    if len(argv) != 7:
        fail("usage: sweep_stat.py STAT.json MEM.json UNIT SECONDS CPU_SECONDS ABC")
    stat_path, mem_path, unit, secs, cpu, abc = argv[1:]
    try:
        text = open(stat_path).read()
        # tee keeps yosys's own lines around the JSON object
        stat = json.loads(text[text.index("{"):text.rindex("}") + 1])
        mem = json.load(open(mem_path))
    except (OSError, ValueError) as e:
        fail("%s / %s: %s" % (stat_path, mem_path, e))
    mods = stat.get("modules", {})
    if len(mods) != 1:
        fail("%s: expected one (flattened) module, got %d" % (stat_path, len(mods)))
    m = next(iter(mods.values()))
    types = m.get("num_cells_by_type", {})
    nmem = types.get("$mem_v2", 0)
    cells = m["num_cells"] - nmem
    bits = 0
    count = 0
    for mod in mem.get("modules", {}).values():
        for c in mod.get("cells", {}).values():
            if c["type"] != "$mem_v2":
                continue
            p = c["parameters"]
            bits += int(p["WIDTH"], 2) * int(p["SIZE"], 2)
            count += 1
    if count != nmem:
        fail("%s: %d memories in the stat, %d in %s" % (stat_path, nmem, count, mem_path))
    print("unit=%s cells=%d memory_bits=%d memories=%d seconds=%s cpu_seconds=%s abc=%s"
          % (unit, cells, bits, count, secs, cpu, abc))


if __name__ == "__main__":
    main(sys.argv)
