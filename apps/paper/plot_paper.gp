# Plots the tables of gfmd_paper (reads the CSVs only; computing is separate):
#   gnuplot -e "dir='paper'" apps/paper/plot_paper.gp     -> dir/fig3.png ... dir/fig7.png
if (!exists("dir")) dir = '.'
if (!exists("widths")) widths = "0 100 10 4 2 1 0.5 0.25 0.177 0.125 0.088 0.0625 0.044"
set terminal pngcairo size 900,650 font ",11"
set datafile separator ","
set grid
set key outside right top
name(w) = (w eq "0") ? "half-space" : sprintf("W = %s", w)
# 13 distinct colours, one per body (gnuplot's own 8 line colours repeat): from the half-space,
# black, through the thick layers (blues, greens) to the thinnest sheets (oranges, reds, purples)
colours = "#000000 #1f3b8c #1f77b4 #17becf #2ca02c #7fbf3f #bcbd22 #e6b800 #ff7f0e #d95f02 #d62728 #e377c2 #7b2d8e"
colour(i) = word(colours, (i - 1) % words(colours) + 1)
sel(w, col) = (strcol(2) eq w) ? column(col) : NaN
f3 = dir.'/fig3_area.csv'

# Fig. 3: A/A0 against sigma0/(E* g), GFMD points, Persson's theory dashed
set output dir.'/fig3.png'
set title "Relative contact area (GFMD points, Persson's theory dashed)"
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "sigma_0 / (E* g)"
set ylabel "A / A_0"
plot for [i=1:words(widths)] f3 using (sel(word(widths,i),4)):(sel(word(widths,i),5)) \
       with linespoints pt (i % 7 + 4) ps 0.8 lc rgb colour(i) title name(word(widths,i)), \
     for [i=1:words(widths)] dir.'/persson_curves.csv' using (sel(word(widths,i),3)):(sel(word(widths,i),4)) \
       with lines dt 2 lc rgb colour(i) notitle

# Fig. 4: A (A0 - A) / A0^2 against the load
set output dir.'/fig4.png'
set title "A(A_0 - A)/A_0^2 against the load"
set ylabel "A (A_0 - A) / A_0^2"
plot for [i=1:words(widths)] dir.'/fig4_area_complement.csv' using (sel(word(widths,i),3)):(sel(word(widths,i),5)) \
       with linespoints pt (i % 7 + 4) ps 0.8 lc rgb colour(i) title name(word(widths,i))

# Fig. 5a: the collapse, load multiplied by c(W)
set output dir.'/fig5a.png'
set title "Collapse: A/A_0 against c(W) sigma_0/(E* g)"
set xlabel "c(W) sigma_0 / (E* g)"
set ylabel "A / A_0"
plot for [i=1:words(widths)] dir.'/fig5a_collapse.csv' using (sel(word(widths,i),4)):(sel(word(widths,i),5)) \
       with points pt (i % 7 + 4) ps 0.8 lc rgb colour(i) title name(word(widths,i))

# Fig. 5b: c(W) and the small-W power law
set output dir.'/fig5b.png'
set title "Correction factor c(W) (line: least-squares power law at small W)"
set xlabel "W = w / lambda_s"
set ylabel "c(W)"
set key inside right top
plot dir.'/fig5b_cW.csv' using 1:2 with points pt 7 ps 1.2 title "c(W) from the collapse", \
     dir.'/fig5b_cW.csv' using 1:3 with lines lw 2 title "fit c ~ W^{alpha}"

# Fig. 6: normalized separation
set output dir.'/fig6.png'
set title "Normalized separation s = 1 - <u>/u_{max}"
unset logscale y
set format y "%g"
set xlabel "sigma_0 / E*"
set ylabel "s"
set key outside right top
plot for [i=1:words(widths)] dir.'/fig6_separation.csv' using (sel(word(widths,i),3)):(sel(word(widths,i),5)) \
       with linespoints pt (i % 7 + 4) ps 0.8 lc rgb colour(i) title name(word(widths,i))

# Fig. 7: theta = U_el/U_ad at three contact areas
set output dir.'/fig7.png'
set title "Adhesion: theta = U_{el}/U_{ad} at fixed contact area"
set logscale xy
set xlabel "W = w / lambda_s"
set ylabel "theta"
set key inside left top
f7 = dir.'/fig7_theta.csv'
at(a, col) = (abs(column(2) - a) < 1e-9) ? column(col) : NaN
plot f7 using (at(0.05,1)):(at(0.05,5)) with linespoints pt 7 title "A/A_0 = 0.05", \
     f7 using (at(0.1,1)):(at(0.1,5)) with linespoints pt 5 title "A/A_0 = 0.1", \
     f7 using (at(0.2,1)):(at(0.2,5)) with linespoints pt 9 title "A/A_0 = 0.2", \
     [0.04:0.3] 400*x**3 with lines dt 2 lc "gray" title "slope 3"

# Fig. 8 (when the study ran with --pulloff): the pull-off stress of the adhesive sheets against W,
# beside theta at A/A0 = 0.1 (Fig. 7) on the right axis
f8 = dir.'/fig8_pulloff.csv'
if (system('test -f '.f8.' && echo 1') eq "1") {
    set output dir.'/fig8.png'
    set title "Pull-off under displacement control (gamma_0 = 5e-4 E* a, rho = a) and theta"
    set logscale xy
    set logscale y2
    set xlabel "W = w / lambda_s"
    set ylabel "|sigma_{pull-off}| / (gamma_0 / rho)"
    set y2label "theta at A/A_0 = 0.1"
    set ytics nomirror
    set y2tics
    set key inside right bottom
    plot f8 using 1:(-column(3)) with linespoints pt 7 ps 1.2 title "pull-off stress", \
         f7 using (at(0.1,1)):(at(0.1,5)) axes x1y2 with linespoints pt 5 dt 2 title "theta (A/A_0 = 0.1)"
    unset y2tics
    unset y2label
    unset logscale y2
    set ytics mirror
}
