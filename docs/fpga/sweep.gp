# sweep.gp — the design-space view (docs/fpga.md, make fpga-sweep): each
# member's logic (yosys generic synth, cells summed over the units; memories
# counted apart, as bits) against the cycle model's cycles per frame, from
# sweep.csv beside it (columns: rtl/fpga/sweep_collect.py).
set terminal svg size 960,640 font "sans,12" dynamic
set output "sweep.svg.tmp"
set datafile separator ","
set title "Albatros VP members: logic against time per frame (cycle model)"
set xlabel "logic, yosys generic synth (cells: gates, muxes, flip-flops; memories excluded)"
set ylabel "time per frame (cycles, mean over the scene's frames)"
set key outside bottom center horizontal
set grid
set logscale y
set offsets graph 0.05, graph 0.15, 0, 0
set format x "%.1s%c"
set format y "%.0s%c"
set datafile columnheaders
plot "sweep.csv" using "cells_total":"cycles_builtin" with points pt 7 ps 1.2 title "built-in scene", \
     "" using "cells_total":"cycles_interpenetrating" with points pt 5 ps 1.0 \
        title "interpenetrating, severity 0.5", \
     "" using "cells_total":"cycles_deep" with points pt 9 ps 1.0 title "deep, severity 0.5", \
     "" using "cells_total":"cycles_builtin":"point" with labels offset 0.6,0.3 left \
        font ",9" notitle
