# gnuplot -e "csv='demo.csv'; out='demo.png'" plot_demo.gp
if (!exists("csv")) csv = 'demo.csv'
if (!exists("out")) out = 'demo.png'
set terminal pngcairo size 1200,500 font ",11"
set output out
set datafile separator ","
set multiplot layout 1,2 title "gfmd demo: self-affine substrate, H = 0.8, lambda_s = 4a, g = 1"
set logscale xy
set key top left
set xlabel "sigma_0 / (E* g)"
set ylabel "A / A_0"
set grid
plot csv using ($2==0 ? $3 : 1/0):4 with linespoints pt 7 title "half-space", \
     csv using ($2==4 ? $3 : 1/0):4 with linespoints pt 5 title "layer W = 4", \
     csv using ($2==1 ? $3 : 1/0):4 with linespoints pt 9 title "layer W = 1", \
     2*x with lines dt 2 lc "gray" title "A/A_0 = 2 sigma_0/(E* g)"
unset logscale y
set ylabel "mean gap / a"
set key top right
plot csv using ($2==0 ? $3 : 1/0):5 with linespoints pt 7 title "half-space", \
     csv using ($2==4 ? $3 : 1/0):5 with linespoints pt 5 title "layer W = 4", \
     csv using ($2==1 ? $3 : 1/0):5 with linespoints pt 9 title "layer W = 1"
unset multiplot
