#!/bin/sh
# Draws a dam-break run (cardiosph dambreak --output DIR) as a PNG: the water at four times,
# coloured by pressure, and the surge front against Martin & Moyce 1952 and Koshizuka & Oka 1996.
# Usage: scripts/plot_dambreak.sh DIR OUTPUT.png   (needs gnuplot)
set -eu
dir=$1
png=$2
command -v gnuplot >/dev/null || { echo "plot_dambreak: gnuplot is not installed" >&2; exit 2; }
for f in snapshots.csv surge_front.csv surge_front_reference.csv; do
  [ -r "$dir/$f" ] || { echo "plot_dambreak: '$dir/$f' is missing (run cardiosph dambreak --output $dir)" >&2; exit 2; }
done
gnuplot <<GNUPLOT
set terminal pngcairo size 1400,900 font "sans,11"
set output "$png.partial"
set datafile separator ","
set multiplot layout 2,3 title "cardiosph dambreak (water 2 x 1, tank 5.366, rho = g = 1, c0 = 20)"
set size ratio -1
set xrange [0:5.366]; set yrange [0:2.5]
set cbrange [0:2]; set palette rgbformulae 33,13,10
unset key
do for [t in "1 2 3 5"] {
  set title sprintf("t = %s (colour: pressure)", t)
  plot "$dir/snapshots.csv" every ::1 using (abs(\$1 - real(t)) < 0.05 ? \$2 : 1/0):3:5 with points pt 7 ps 0.25 lc palette
}
set size noratio
set autoscale; set xrange [0:2]; set yrange [1:3]
set title "surge front Z = x / a against T = t sqrt(g / a)"
set xlabel "T"; set ylabel "Z"; set key left top
plot "$dir/surge_front.csv" every ::1 using 3:4 with lines lw 2 title "cardiosph", \
     "$dir/surge_front_reference.csv" every ::1 using (stringcolumn(1) eq "martin_moyce" ? \$2 : 1/0):3 with points pt 7 ps 1.2 title "Martin and Moyce 1952", \
     "$dir/surge_front_reference.csv" every ::1 using (stringcolumn(1) eq "koshizuka_oka" ? \$2 : 1/0):3 with points pt 5 ps 1.2 title "Koshizuka and Oka 1996"
unset multiplot
GNUPLOT
mv "$png.partial" "$png"
echo "plot_dambreak: wrote $png"
