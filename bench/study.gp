# The integrator study's two charts, from bench/results/stability.csv and
# work_precision.csv (written by sb_study; bench/study.sh runs both).
#
#   gnuplot bench/study.gp                      (from the repository root)
#   gnuplot -e "results='DIR'" bench/study.gp
if (!exists("results")) results = "bench/results"
stability = results . "/stability.csv"
precision = results . "/work_precision.csv"
names = "verlet velocity_verlet position_verlet symplectic_euler explicit_euler implicit_euler pbd xpbd"

set terminal pngcairo size 1000,700 enhanced font "sans,11"
set datafile separator whitespace
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set key outside right top box opaque

# Rows of integrator `name` as "x y" from columns cx and cy of a CSV.
rows(file, name, cx, cy) = sprintf("< awk -F, '!/^#/ && $0 !~ /^k,|^integrator,/ && $%d == \"%s\" { print $%d, $%d }' %s", \
                                   (file eq stability ? 4 : 1), name, cx, cy, file)

set output results . "/stability.png"
set title "Largest stable step against stiffness (12 x 12 sheet, left edge fixed; capped at 100 x 2/{/Symbol w}_{max})"
set xlabel "bond stiffness k (N/m)"
set ylabel "largest stable dt (s)"
plot for [i=1:words(names)] rows(stability, word(names, i), 1, 5) using 1:2 with linespoints lw 2 pt i title word(names, i) noenhanced, \
     rows(stability, "verlet", 1, 3) using 1:2 with lines lw 3 dt 2 lc rgb "black" title "2/{/Symbol w}_{max}"

set output results . "/work_precision.png"
set title "Work-precision: error after 0.2 s of a 0.5 N push at the sheet's middle, against CPU time"
set xlabel "CPU time of the run (s)"
set ylabel "largest vertex error (m)"
plot for [i=1:words(names)] rows(precision, word(names, i), 5, 6) using 1:2 with linespoints lw 2 pt i title word(names, i) noenhanced
