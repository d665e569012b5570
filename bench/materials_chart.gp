# The speed-accuracy chart of the tissue models (issue 29): the error
# against ccx's C3D10 (absolute, per cent) against the cost of a Verlet
# step (fast kernels, 2 threads), log axes, a line per model, each point
# labelled with its vertex count; one panel for the cantilever's tip
# deflection, one for the indentation's force. Reads and writes
# bench/results/materials_chart.{csv,png}; bench/materials_chart.sh runs it.
results = "bench/results"
data = results . "/materials_chart.csv"
rows(case, model) = sprintf("< awk -F, '!/^#/ && $1 == \"%s\" && $2 == \"%s\" { e = $6 < 0 ? -$6 : $6; print $8, e, $4, ($6 < 0 ? \"-\" : \"+\") }' %s", case, model, data)
models = "springs corotated corotated_quadratic"
set terminal pngcairo size 1500,640 enhanced font "sans,11"
set output results . "/materials_chart.png"
set xlabel "wall time of a Verlet step, fast kernels, 2 threads (µs)"
set ylabel "|error| against CalculiX C3D10 (%)"
set logscale xy
set grid
set key top right box opaque
set multiplot layout 1,2 title "Tissue models: error against cost (E 3.5 kPa, {/Symbol n} 0.45); labels: vertices, (+) above, (-) below the FEM answer"
do for [c in "cantilever indentation"] {
    set title (c eq "cantilever" ? "cantilever 100 x 20 x 20 mm: tip deflection under a tip traction" \
                                 : "block 20 x 20 x 10 mm, sphere r 5 mm pressed 1 mm: force")
    plot for [m=1:words(models)] rows(c, word(models, m)) using 1:2 with linespoints lw 2 pt 7 ps 1.2 lc m \
             title word(models, m) noenhanced, \
         for [m=1:words(models)] rows(c, word(models, m)) using 1:2:(sprintf("%s (%s)", strcol(3), strcol(4))) \
             with labels offset 0,1.1 font "sans,9" tc lt m notitle
}
unset multiplot
