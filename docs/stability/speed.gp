# speed against accuracy, written by albatros stability --report
set terminal pngcairo size 1100,750 noenhanced
set output 'docs/stability/speed.png'
set title 'Speed against accuracy (each point: a method or configuration)'
set xlabel 'host milliseconds per frame (log)'
set logscale x
set ylabel 'pixels whose face differs from the exact reference, % (log; 0 drawn at 0.001)'
set logscale y
set grid
set key top right
plot 'docs/stability/speed-points.dat' using 1:2 with points pt 7 title 'configurations', \
     '' using 1:2:4 with labels offset 0.5,0.6 left rotate by 20 font ',7' notitle, \
     '' using ($3 == 1 ? $1 : NaN):2 smooth unique with linespoints lw 2 pt 6 ps 2 title 'Pareto front'
