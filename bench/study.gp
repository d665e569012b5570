# The integrator study's charts, from the CSVs in bench/results written by
# sb_study (bench/study.sh runs both): stability.png, work_precision.png
# (push at the middle), work_precision_corner.png (push at a free corner),
# model_accuracy.png and lod_accuracy.png.
#
#   gnuplot bench/study.gp                      (from the repository root)
#   gnuplot -e "results='DIR'" bench/study.gp
if (!exists("results")) results = "bench/results"
stability = results . "/stability.csv"
names = "verlet velocity_verlet position_verlet symplectic_euler explicit_euler implicit_euler pbd xpbd vbd"

set terminal pngcairo size 1000,700 enhanced font "sans,11"
set linetype 9 lc rgb "#8c564b" # the ninth integrator (vbd) gets its own colour
set datafile separator whitespace
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set key outside right top box opaque

# Rows whose column `ckey` equals `name`, as "x y" from columns cx and cy
# of a CSV (comment lines and the header skipped).
rows_by(file, ckey, name, cx, cy) = sprintf("< awk -F, '!/^#/ && NR > 1 && $%d == \"%s\" { print $%d, $%d }' %s", \
                                            ckey, name, cx, cy, file)
rows(file, name, cx, cy) = rows_by(file, (file eq stability ? 4 : 1), name, cx, cy)

set output results . "/stability.png"
set title "Largest stable step against stiffness (12 x 12 sheet, left edge fixed; capped at 100 x 2/{/Symbol w}_{max})"
set xlabel "bond stiffness k (N/m)"
set ylabel "largest stable dt (s)"
plot for [i=1:words(names)] rows(stability, word(names, i), 1, 5) using 1:2 with linespoints lw 2 pt i title word(names, i) noenhanced, \
     rows(stability, "verlet", 1, 3) using 1:2 with lines lw 3 dt 2 lc rgb "black" title "2/{/Symbol w}_{max}"

set xlabel "CPU time of the run (s)"
set ylabel "largest vertex error (m)"
do for [where in "middle corner large"] {
    precision = results . "/work_precision" . (where eq "middle" ? "" : "_" . where) . ".csv"
    set output results . "/work_precision" . (where eq "middle" ? "" : "_" . where) . ".png"
    set title (where eq "large" ? "Work-precision at scale: 48 x 48 sheet, fast kernels, a 0.5 N push at the middle for 0.2 s" : "Work-precision: error after 0.2 s of a 0.5 N push at the sheet's " . (where eq "middle" ? "middle" : "free corner") . ", against CPU time")
    plot for [i=1:words(names)] rows(precision, word(names, i), 5, 6) using 1:2 with linespoints lw 2 pt i title word(names, i) noenhanced
}

# Model accuracy: three panels against the load, a curve per model and load.
accuracy = results . "/model_accuracy.csv"
cases(model, load, cy) = sprintf("< awk -F, '!/^#/ && NR > 1 && $1 == \"%s\" && $2 == \"%s\" { print $3, $%d }' %s", \
                                 model, load, cy, accuracy)
models = "springs springs+angle"
loads = "stretch shear"
set output results . "/model_accuracy.png"
set terminal pngcairo size 1500,520 enhanced font "sans,11"
unset logscale
set format x "%g"
set format y "%g"
set key inside left top box opaque
set multiplot layout 1,3 title "Shape kept at static equilibrium: 12 x 12 sheet, left edge fixed, total force F on the right edge (stretch: +x, shear: +y)"
panel_cols = "4 5 7"
panel_titles = "'loaded edge displacement (m)' 'RMS relative triangle area change' 'RMS corner angle change (degrees)'"
do for [p=1:3] {
    set title word(panel_titles, p)
    set xlabel "total force F (N)"
    set ylabel word(panel_titles, p)
    plot for [m=1:2] for [l=1:2] cases(word(models, m), word(loads, l), int(word(panel_cols, p))) using 1:2 \
         with linespoints lw 2 pt (2 * m + l) dt l lc m title word(models, m) . ", " . word(loads, l) noenhanced
}
unset multiplot

# Level of detail: each level's error against the full model, and its step's cost.
lod = results . "/lod_accuracy.csv"
set output results . "/lod_accuracy.png"
set terminal pngcairo size 1000,600 enhanced font "sans,11"
set title "Level of detail: the default scene's sheet after 1 s, each simplified level against the full model"
set logscale xy
set format x "%g"
set format y "%g"
set xlabel "vertices"
set ylabel "distance from the full model's same vertices at the end (m)"
set y2label "CPU ms per step (fast kernels, 1 thread)"
set logscale y2
set y2tics
set ytics nomirror
set key inside left top box opaque
set datafile separator comma
plot sprintf("< awk -F, '!/^#/ && NR > 3' %s", lod) using 1:4 with linespoints lw 2 pt 7 title "RMS over the level's vertices", \
     sprintf("< awk -F, '!/^#/ && NR > 3' %s", lod) using 1:5 with linespoints lw 2 pt 5 title "largest", \
     sprintf("< awk -F, '!/^#/ && NR > 2' %s", lod) using 1:3 axes x1y2 with linespoints lw 2 pt 9 dt 2 title "ms per step"
