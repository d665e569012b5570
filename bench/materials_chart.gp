# The speed-accuracy chart of the tissue models (issue 29): the cantilever's
# tip deflection error against ccx's C3D10 (absolute, per cent) against the
# cost of a Verlet step (fast kernels, 2 threads), log axes, a line per
# model, each point labelled with its vertex count. Reads and writes
# bench/results/materials_chart.{csv,png}; bench/materials_chart.sh runs it.
results = "bench/results"
data = results . "/materials_chart.csv"
rows(model) = sprintf("< awk -F, '!/^#/ && $1 == \"%s\" { e = $5 < 0 ? -$5 : $5; print $7, e, $3, ($5 < 0 ? \"-\" : \"+\") }' %s", model, data)
models = "springs corotated corotated_quadratic"
set terminal pngcairo size 900,640 enhanced font "sans,11"
set output results . "/materials_chart.png"
set title "Tissue models: cantilever tip deflection error against cost (E 3.5 kPa, {/Symbol n} 0.45)\nlabels: vertices, (+) too soft, (-) too stiff"
set xlabel "wall time of a Verlet step, fast kernels, 2 threads (µs)"
set ylabel "|error| against CalculiX C3D10 (%)"
set logscale xy
set grid
set key top right box opaque
plot for [m=1:words(models)] rows(word(models, m)) using 1:2 with linespoints lw 2 pt 7 ps 1.2 lc m \
         title word(models, m) noenhanced, \
     for [m=1:words(models)] rows(word(models, m)) using 1:2:(sprintf("%s (%s)", strcol(3), strcol(4))) \
         with labels offset 0,1.1 font "sans,9" tc lt m notitle
