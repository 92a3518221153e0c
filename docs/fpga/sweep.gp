# sweep.gp — the design-space view (docs/fpga.md): hardware cost (yosys's
# generic gates, make fpga-sweep) against the cycle model's cycles per frame,
# one point per member, from sweep.csv beside it.
set terminal svg size 900,600 font "sans,12"
set output "sweep.svg"
set datafile separator ","
set title "Albatros VP members: gates against time per frame (built-in scene, cycle model)"
set xlabel "yosys generic synth, gates (cells, ROM, texture memory and FIFO excluded)"
set ylabel "cycles per frame, built-in scene (mean of 4 frames)"
set key top right box
set grid
set logscale y
set format x "%.0s%c"
plot "sweep.csv" using 3:13 skip 1 with points pt 7 ps 1.2 title "built-in scene", \
     "" using 3:14 skip 1 with points pt 5 ps 1.0 title "interpenetrating, severity 0.5", \
     "" using 3:15 skip 1 with points pt 9 ps 1.0 title "deep, severity 0.5", \
     "" using 3:13:1 skip 1 with labels offset 0.8,0.6 left font ",9" notitle
