# The load-unload curve of gfmd_load_unload:  gnuplot -e "csv='load_unload.csv'" examples/load_unload.gp
if (!exists("csv")) csv = 'load_unload.csv'
if (!exists("out")) out = 'load_unload.png'
set terminal pngcairo size 1000,420 font ",11"
set output out
set datafile separator ","
set key autotitle columnhead
set grid
set multiplot layout 1,2
set xlabel "mean position of the surface, <z> / a"
set ylabel "mean pressure / E*"
plot csv using (strcol(1) eq "load" ? $2 : NaN):3 with linespoints pt 7 ps 0.6 lc rgb "#1f77b4" title "loading", \
     csv using (strcol(1) eq "unload" ? $2 : NaN):3 with linespoints pt 5 ps 0.6 lc rgb "#d62728" title "unloading", \
     0 with lines lc rgb "gray" notitle
set ylabel "A / A_0"
plot csv using (strcol(1) eq "load" ? $2 : NaN):4 with linespoints pt 7 ps 0.6 lc rgb "#1f77b4" title "loading", \
     csv using (strcol(1) eq "unload" ? $2 : NaN):4 with linespoints pt 5 ps 0.6 lc rgb "#d62728" title "unloading"
unset multiplot
