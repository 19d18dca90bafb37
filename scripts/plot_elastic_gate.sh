#!/bin/sh
# Draws an elastic-gate run (cardiosph elastic-gate --output DIR) as a PNG: the free corner's
# displacement dx(t) and dy(t) against the experiment of Antoci et al. 2007 (tip_experiment.csv,
# digitised; its x is our -dx) and SPHinXsys's run of the same setup (tip_reference.csv).
# Usage: scripts/plot_elastic_gate.sh DIR OUTPUT.png   (needs gnuplot)
set -eu
dir=$1
png=$2
command -v gnuplot >/dev/null || { echo "plot_elastic_gate: gnuplot is not installed" >&2; exit 2; }
for f in observers.csv tip_reference.csv tip_experiment.csv; do
  [ -r "$dir/$f" ] || { echo "plot_elastic_gate: '$dir/$f' is missing (run cardiosph elastic-gate --output $dir)" >&2; exit 2; }
done
gnuplot <<GNUPLOT
set terminal pngcairo size 1000,600 font "sans,11" noenhanced
set output "$png.partial"
set datafile separator ","
set title "cardiosph elastic-gate: displacement of the gate's free corner"
set xlabel "t [ms]"; set ylabel "displacement [mm]"; set key right center
set grid
plot "$dir/observers.csv" every ::1 using 1:2 with lines lw 2 lc rgb "#1b9e77" title "cardiosph dx", \
     "$dir/observers.csv" every ::1 using 1:3 with lines lw 2 lc rgb "#7570b3" title "cardiosph dy", \
     "$dir/tip_reference.csv" every ::1 using 1:2 with points pt 7 ps 1.2 lc rgb "#1b9e77" title "SPHinXsys dx", \
     "$dir/tip_reference.csv" every ::1 using 1:3 with points pt 5 ps 1.2 lc rgb "#7570b3" title "SPHinXsys dy", \
     "$dir/tip_experiment.csv" every ::1 using 1:(-\$2) with points pt 9 ps 1.6 lc rgb "#d95f02" title "experiment dx (Antoci et al. 2007)", \
     "$dir/tip_experiment.csv" every ::1 using 4:5 with points pt 11 ps 1.6 lc rgb "#e7298a" title "experiment dy (Antoci et al. 2007)"
GNUPLOT
mv "$png.partial" "$png"
echo "plot_elastic_gate: wrote $png"
