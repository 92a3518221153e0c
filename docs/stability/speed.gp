# speed against accuracy, written by albatros stability --report
set terminal pngcairo size 1400,800 font ',10' noenhanced
set output 'docs/stability/speed.png'
set title 'Speed against accuracy: each point a method, or an Albatros configuration at a fidelity (numbered as in the key)'
set xlabel 'host time per frame, ms (log scale)'
set logscale x
set ylabel 'pixels whose face differs from the exact reference, % (log scale; 0 drawn at 0.001)'
set logscale y
set grid
set key outside right top vertical font ',9' spacing 1.1 title 'points'
set rmargin 38
plot 'docs/stability/speed-points.dat' index 0 using 1:2 with points pt 7 ps 1.3 lc rgb '#1f77b4' notitle, \
     '' index 0 using 1:2:5 with labels left offset char 0.7,0.6 font ',9' notitle, \
     '' index 1 using 1:2 with lines lw 2 lc rgb '#d62728' title 'Pareto front (nothing faster and more accurate)', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '1  zbuffer', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '2  scanline-zbuffer', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '3  watkins', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '4  watkins-nosplit', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '5  warnock', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '6  painter', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '7  raycast', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '8  vp, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '9  vp, timed', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '10  vp, cycle', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '11  vp-bound-none, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '12  vp-bound-box, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '13  vp-bound-bisector, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '14  vp-edge-2, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '15  vp-edge-4, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '16  vp-depth20, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '17  vp-depth16, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '18  vp-aa1, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '19  vp-aa2, functional', \
     keyentry with points pt 7 ps 0 lc rgb '#ffffff' title '20  reference'
