# stability chart, written by albatros stability --report
set terminal pngcairo size 1600,2000 font ',9' noenhanced
set output 'docs/stability/stability.png'
set multiplot layout 5,2 title 'Pixels whose face differs from the exact reference (%) against severity'
set key outside right font ',7'
set grid
set datafile missing 'NaN'
set title 'sliver'
set yrange [0:1]
set xtics ('10' 1, '1' 2, '0.1' 3, '0.01' 4)
plot 'docs/stability/stability-sliver.dat' using 1:2 with linespoints title 'zbuffer', \
     'docs/stability/stability-sliver.dat' using 1:3 with linespoints title 'scanline-zbuffer', \
     'docs/stability/stability-sliver.dat' using 1:4 with linespoints title 'watkins', \
     'docs/stability/stability-sliver.dat' using 1:5 with linespoints title 'watkins-nosplit', \
     'docs/stability/stability-sliver.dat' using 1:6 with linespoints title 'warnock', \
     'docs/stability/stability-sliver.dat' using 1:7 with linespoints title 'painter', \
     'docs/stability/stability-sliver.dat' using 1:8 with linespoints title 'raycast', \
     'docs/stability/stability-sliver.dat' using 1:9 with linespoints title 'vp', \
     'docs/stability/stability-sliver.dat' using 1:10 with linespoints title 'vp-bound-none', \
     'docs/stability/stability-sliver.dat' using 1:11 with linespoints title 'vp-bound-box', \
     'docs/stability/stability-sliver.dat' using 1:12 with linespoints title 'vp-bound-bisector', \
     'docs/stability/stability-sliver.dat' using 1:13 with linespoints title 'vp-edge-2', \
     'docs/stability/stability-sliver.dat' using 1:14 with linespoints title 'vp-edge-4', \
     'docs/stability/stability-sliver.dat' using 1:15 with linespoints title 'vp-depth20', \
     'docs/stability/stability-sliver.dat' using 1:16 with linespoints title 'vp-depth16', \
     'docs/stability/stability-sliver.dat' using 1:17 with linespoints title 'vp-aa1', \
     'docs/stability/stability-sliver.dat' using 1:18 with linespoints title 'vp-aa2'
set title 'crossing-z0'
set yrange [0:1]
set xtics ('0' 1, '0.3' 2, '0.7' 3, '0.95' 4)
plot 'docs/stability/stability-crossing-z0.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-crossing-z0.dat' using 1:18 with linespoints title ''
set title 'far'
set yrange [0:41.5363]
set xtics ('10' 1, '1000' 2, '10000' 3, '1e+06' 4)
plot 'docs/stability/stability-far.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-far.dat' using 1:18 with linespoints title ''
set title 'texture-far'
set yrange [0:1]
set xtics ('10' 1, '10000' 2, '1e+08' 3, '1e+12' 4)
plot 'docs/stability/stability-texture-far.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-texture-far.dat' using 1:18 with linespoints title ''
set title 'interpenetrating'
set yrange [0:10.1426]
set xtics ('45' 1, '5' 2, '0.5' 3, '0.01' 4)
plot 'docs/stability/stability-interpenetrating.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-interpenetrating.dat' using 1:18 with linespoints title ''
set title 'cyclic'
set yrange [0:3.64098]
set xtics ('0.05' 1, '0.1' 2, '0.2' 3, '0.4' 4)
plot 'docs/stability/stability-cyclic.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-cyclic.dat' using 1:18 with linespoints title ''
set title 'degenerate'
set yrange [0:1]
set xtics ('0.1' 1, '0.001' 2, '1e-06' 3, '1e-09' 4)
plot 'docs/stability/stability-degenerate.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-degenerate.dat' using 1:18 with linespoints title ''
set title 'tjunction'
set yrange [0:1.79445]
set xtics ('2' 1, '8' 2, '32' 3, '64' 4)
plot 'docs/stability/stability-tjunction.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-tjunction.dat' using 1:18 with linespoints title ''
set title 'deep'
set yrange [0:1]
set xtics ('1' 1, '8' 2, '32' 3, '64' 4)
plot 'docs/stability/stability-deep.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-deep.dat' using 1:18 with linespoints title ''
set title 'coords'
set yrange [0:15.2055]
set xtics ('0' 1, '10' 2, '25' 3, '40' 4)
plot 'docs/stability/stability-coords.dat' using 1:2 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:3 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:4 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:5 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:6 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:7 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:8 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:9 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:10 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:11 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:12 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:13 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:14 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:15 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:16 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:17 with linespoints title '', \
     'docs/stability/stability-coords.dat' using 1:18 with linespoints title ''
unset multiplot
