# stability chart, written by albatros stability --report
set terminal pngcairo size 1600,1710 font ',10' noenhanced
set output 'docs/stability/stability.png'
set multiplot layout 5,2 title "Pixels whose face differs from the exact reference, %, against each family's severity (more severe to the right)\nno configuration differs anywhere on: texture-far"
set grid
set datafile missing 'NaN'
unset key
set ylabel 'pixels wrong, %'
set linetype 1 lc rgb '#1f77b4' lw 1.6 dt 1 pt 5 ps 1.1
set linetype 2 lc rgb '#ff7f0e' lw 1.6 dt 1 pt 7 ps 1.1
set linetype 3 lc rgb '#2ca02c' lw 1.6 dt 1 pt 9 ps 1.1
set linetype 4 lc rgb '#d62728' lw 1.6 dt 1 pt 11 ps 1.1
set linetype 5 lc rgb '#9467bd' lw 1.6 dt 1 pt 13 ps 1.1
set linetype 6 lc rgb '#8c564b' lw 1.6 dt 1 pt 15 ps 1.1
set linetype 7 lc rgb '#e377c2' lw 1.6 dt 1 pt 5 ps 1.1
set linetype 8 lc rgb '#17becf' lw 1.6 dt 2 pt 4 ps 1.1
set linetype 9 lc rgb '#bcbd22' lw 1.6 dt 2 pt 6 ps 1.1
set linetype 10 lc rgb '#000000' lw 1.6 dt 2 pt 8 ps 1.1
set linetype 11 lc rgb '#e6ab02' lw 1.6 dt 2 pt 10 ps 1.1
set linetype 12 lc rgb '#a6761d' lw 1.6 dt 2 pt 12 ps 1.1
set linetype 13 lc rgb '#1b9e77' lw 1.6 dt 2 pt 14 ps 1.1
set linetype 14 lc rgb '#d95f02' lw 1.6 dt 2 pt 1 ps 1.1
set linetype 15 lc rgb '#7570b3' lw 1.6 dt 2 pt 2 ps 1.1
set linetype 16 lc rgb '#e7298a' lw 1.6 dt 2 pt 3 ps 1.1
set linetype 17 lc rgb '#66a61e' lw 1.6 dt 2 pt 4 ps 1.1
set title 'sliver'
set xlabel 'severity: tip angle, degrees'
set yrange [0:0.134205]
set xtics ('10' 1, '1' 2, '0.1' 3, '0.01' 4)
plot 'docs/stability/stability-sliver.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-sliver.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-sliver.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-sliver.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-sliver.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-sliver.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-sliver.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-sliver.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-sliver.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-sliver.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-sliver.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-sliver.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-sliver.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-sliver.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-sliver.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-sliver.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-sliver.dat' using 1:18 with linespoints ls 17 notitle
set title 'crossing-z0'
set xlabel 'severity: fraction of the face behind Z = 0'
set yrange [0:0.078085]
set xtics ('0' 1, '0.3' 2, '0.7' 3, '0.95' 4)
plot 'docs/stability/stability-crossing-z0.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-crossing-z0.dat' using 1:18 with linespoints ls 17 notitle
set title 'far'
set xlabel 'severity: distance of the front face (gap 1)'
set yrange [0:45.4922]
set xtics ('10' 1, '1000' 2, '10000' 3, '1e+06' 4)
plot 'docs/stability/stability-far.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-far.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-far.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-far.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-far.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-far.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-far.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-far.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-far.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-far.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-far.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-far.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-far.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-far.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-far.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-far.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-far.dat' using 1:18 with linespoints ls 17 notitle
set title 'interpenetrating'
set xlabel 'severity: angle between the planes, degrees'
set yrange [0:11.1085]
set xtics ('45' 1, '5' 2, '0.5' 3, '0.01' 4)
plot 'docs/stability/stability-interpenetrating.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-interpenetrating.dat' using 1:18 with linespoints ls 17 notitle
set title 'cyclic'
set xlabel 'severity: bar width / distance between crossings'
set yrange [0:3.98774]
set xtics ('0.05' 1, '0.1' 2, '0.2' 3, '0.4' 4)
plot 'docs/stability/stability-cyclic.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-cyclic.dat' using 1:18 with linespoints ls 17 notitle
set title 'degenerate'
set xlabel 'severity: triangle height / base'
set yrange [0:0.14743]
set xtics ('0.1' 1, '0.001' 2, '1e-06' 3, '1e-09' 4)
plot 'docs/stability/stability-degenerate.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-degenerate.dat' using 1:18 with linespoints ls 17 notitle
set title 'tjunction'
set xlabel 'severity: rows of T-junctions'
set yrange [0:1.96535]
set xtics ('2' 1, '8' 2, '32' 3, '64' 4)
plot 'docs/stability/stability-tjunction.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-tjunction.dat' using 1:18 with linespoints ls 17 notitle
set title 'deep'
set xlabel 'severity: depth complexity at the centre'
set yrange [0:0.71944]
set xtics ('1' 1, '8' 2, '32' 3, '64' 4)
plot 'docs/stability/stability-deep.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-deep.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-deep.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-deep.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-deep.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-deep.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-deep.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-deep.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-deep.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-deep.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-deep.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-deep.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-deep.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-deep.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-deep.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-deep.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-deep.dat' using 1:18 with linespoints ls 17 notitle
set title 'coords'
set xlabel 'severity: log10 of the coordinate scale'
set yrange [0:16.6536]
set xtics ('0' 1, '10' 2, '25' 3, '40' 4)
plot 'docs/stability/stability-coords.dat' using 1:2 with linespoints ls 1 notitle, \
     'docs/stability/stability-coords.dat' using 1:3 with linespoints ls 2 notitle, \
     'docs/stability/stability-coords.dat' using 1:4 with linespoints ls 3 notitle, \
     'docs/stability/stability-coords.dat' using 1:5 with linespoints ls 4 notitle, \
     'docs/stability/stability-coords.dat' using 1:6 with linespoints ls 5 notitle, \
     'docs/stability/stability-coords.dat' using 1:7 with linespoints ls 6 notitle, \
     'docs/stability/stability-coords.dat' using 1:8 with linespoints ls 7 notitle, \
     'docs/stability/stability-coords.dat' using 1:9 with linespoints ls 8 notitle, \
     'docs/stability/stability-coords.dat' using 1:10 with linespoints ls 9 notitle, \
     'docs/stability/stability-coords.dat' using 1:11 with linespoints ls 10 notitle, \
     'docs/stability/stability-coords.dat' using 1:12 with linespoints ls 11 notitle, \
     'docs/stability/stability-coords.dat' using 1:13 with linespoints ls 12 notitle, \
     'docs/stability/stability-coords.dat' using 1:14 with linespoints ls 13 notitle, \
     'docs/stability/stability-coords.dat' using 1:15 with linespoints ls 14 notitle, \
     'docs/stability/stability-coords.dat' using 1:16 with linespoints ls 15 notitle, \
     'docs/stability/stability-coords.dat' using 1:17 with linespoints ls 16 notitle, \
     'docs/stability/stability-coords.dat' using 1:18 with linespoints ls 17 notitle
set title 'series'
unset xlabel
unset ylabel
unset border
unset tics
unset grid
set xrange [0:1]
set yrange [0:1]
set key center center vertical maxrows 9 width 2 font ',11' samplen 4
plot NaN with linespoints ls 1 title 'zbuffer', \
     NaN with linespoints ls 2 title 'scanline-zbuffer', \
     NaN with linespoints ls 3 title 'watkins', \
     NaN with linespoints ls 4 title 'watkins-nosplit', \
     NaN with linespoints ls 5 title 'warnock', \
     NaN with linespoints ls 6 title 'painter', \
     NaN with linespoints ls 7 title 'raycast', \
     NaN with linespoints ls 8 title 'vp', \
     NaN with linespoints ls 9 title 'vp-bound-none', \
     NaN with linespoints ls 10 title 'vp-bound-box', \
     NaN with linespoints ls 11 title 'vp-bound-bisector', \
     NaN with linespoints ls 12 title 'vp-edge-2', \
     NaN with linespoints ls 13 title 'vp-edge-4', \
     NaN with linespoints ls 14 title 'vp-depth20', \
     NaN with linespoints ls 15 title 'vp-depth16', \
     NaN with linespoints ls 16 title 'vp-aa1', \
     NaN with linespoints ls 17 title 'vp-aa2'
unset multiplot
