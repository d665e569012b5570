# Steps per second against vertex count, log-log: softbond's fast kernels
# with 1 and 2 threads, the scalar reference, and LAMMPS with 1 and 2 MPI
# workers, from bench/results/throughput.csv and bench/results/lammps.csv.
# Sheets are solid lines with filled points, icospheres dashed with open ones
# (the numbering variants of the 655k icosphere, unordered and shuffled, left
# out: one point per mesh size).
#
#
#   gnuplot bench/plot.gp                       (from the repository root)
#   gnuplot -e "results='DIR'" bench/plot.gp    (CSVs in DIR, PNG written there)
#   gnuplot -e "terms='all'" bench/plot.gp      (bench/run.sh --all-terms: the
#       *_all_terms files, and softbond's default terms with 2 threads beside)
if (!exists("results")) results = "bench/results"
if (!exists("terms")) terms = "default"
all = (terms eq "all")
suffix = all ? "_all_terms" : ""
throughput = results . "/throughput" . suffix . ".csv"
lammps = results . "/lammps" . suffix . ".csv"
out = results . "/throughput" . suffix . ".png"
default_terms = results . "/throughput.csv"

set terminal pngcairo size 1100,750 enhanced font "sans,11"
set output out
set datafile separator whitespace
set logscale xy
set format x "10^{%L}"
set format y "10^{%L}"
set xlabel "vertices"
set ylabel "steps per second"
if (all) {
    set title "all terms: softbond (bond, angle, stretch-bend, damped spring, hinge; Verlet)\nvs LAMMPS with the terms it has (bond, angle, dihedral table; NVE)"
} else {
    set title "softbond step throughput (bond + angle + stretch-bend, Verlet) vs LAMMPS (bond + angle, NVE)"
}
set grid xtics ytics mxtics mytics lc rgb "#dddddd"
set key outside right top box opaque
set xrange [5e3:2e6]

# Rows of a CSV as "vertices steps_per_s", filtered with awk.
rows(mesh, kernels, threads, file) = sprintf("< awk -F, '!/^#/ && $1 !~ /unordered|shuffled/ && $2 == \"%s\" && $10 == \"%s\" && $11 == %d && $15 != \"\" { print $3, $15 }' %s", mesh, kernels, threads, file)
ours(mesh, kernels, threads) = rows(mesh, kernels, threads, throughput)
theirs(mesh, workers) = sprintf("< awk -F, '!/^#/ && $1 ~ /^%s_/ && $3 == %d && $7 != \"\" { print $2, $7 }' %s", mesh, workers, lammps)

# With all terms, softbond's default terms beside (a macro: nothing otherwise).
default_terms_line = all ? ', rows("sheet", "fast", 2, default_terms) using 1:2 with lines lc rgb "#2ca02c" lw 2 dt 3 title "default terms, 2 threads (sheet, throughput.csv)"' : ""

set style line 1 lc rgb "#1f77b4" lw 2 pt 7 ps 1.3
set style line 2 lc rgb "#2ca02c" lw 2 pt 5 ps 1.3
set style line 3 lc rgb "#7f7f7f" lw 2 pt 9 ps 1.3
set style line 4 lc rgb "#d62728" lw 2 pt 13 ps 1.3
set style line 5 lc rgb "#ff7f0e" lw 2 pt 11 ps 1.3
set style line 11 lc rgb "#1f77b4" lw 2 dt 2 pt 6 ps 1.3
set style line 12 lc rgb "#2ca02c" lw 2 dt 2 pt 4 ps 1.3
set style line 13 lc rgb "#7f7f7f" lw 2 dt 2 pt 8 ps 1.3
set style line 14 lc rgb "#d62728" lw 2 dt 2 pt 12 ps 1.3
set style line 15 lc rgb "#ff7f0e" lw 2 dt 2 pt 10 ps 1.3

# The issue's targets: 1000 steps/s at 100k vertices, 100 at 1M (2 threads);
# with all terms only the first.
$targets << EOD
99856 1000
1000000 100
EOD

plot \
  ours("sheet", "fast", 1)          using 1:2 with linespoints ls 1  title "fast, 1 thread (sheet)", \
  ours("icosphere", "fast", 1)      using 1:2 with linespoints ls 11 title "fast, 1 thread (icosphere)", \
  ours("sheet", "fast", 2)          using 1:2 with linespoints ls 2  title "fast, 2 threads (sheet)", \
  ours("icosphere", "fast", 2)      using 1:2 with linespoints ls 12 title "fast, 2 threads (icosphere)", \
  ours("sheet", "reference", 1)     using 1:2 with linespoints ls 3  title "reference, 1 thread (sheet)", \
  ours("icosphere", "reference", 1) using 1:2 with linespoints ls 13 title "reference, 1 thread (icosphere)", \
  theirs("sheet", 1)                using 1:2 with linespoints ls 4  title "LAMMPS, 1 worker (sheet)", \
  theirs("icosphere", 1)            using 1:2 with linespoints ls 14 title "LAMMPS, 1 worker (icosphere)", \
  theirs("sheet", 2)                using 1:2 with linespoints ls 5  title "LAMMPS, 2 MPI workers (sheet)", \
  theirs("icosphere", 2)            using 1:2 with linespoints ls 15 title "LAMMPS, 2 MPI workers (icosphere)", \
  $targets every ::0::(all ? 0 : 1) using 1:2 with points pt 3 ps 2.5 lw 2 lc rgb "black" title "targets (2 threads, sheet)" \
  @default_terms_line
