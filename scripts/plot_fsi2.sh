#!/bin/sh
# Draws a Turek-Hron FSI2 run (cardiosph turek-hron-fsi2 --output DIR) as a PNG: the flow at the end
# of the run coloured by vorticity with the cylinder and bar in black, and the bar-tip displacement
# y(t) against the band 0.0123 +- 0.806 of Turek & Hron 2006 (nondimensional, D = 1). An optional
# third argument is a comma-separated file "time,dx,dy" (no header) of another code's tip, drawn beside ours.
# Usage: scripts/plot_fsi2.sh DIR OUTPUT.png [OTHER_TIP.txt OTHER_NAME]   (needs gnuplot)
set -eu
dir=$1
png=$2
other=${3:-}
other_name=${4:-other}
command -v gnuplot >/dev/null || { echo "plot_fsi2: gnuplot is not installed" >&2; exit 2; }
for f in snapshot.csv observers.csv; do
  [ -r "$dir/$f" ] || { echo "plot_fsi2: '$dir/$f' is missing (run cardiosph turek-hron-fsi2 --output $dir)" >&2; exit 2; }
done
[ -z "$other" ] || [ -r "$other" ] || { echo "plot_fsi2: '$other' is not readable" >&2; exit 2; }
extra=""
[ -z "$other" ] || extra=", \"$other\" using 1:3 with lines lw 1.5 lc rgb '#d95f02' title \"$other_name\""
gnuplot <<GNUPLOT
set terminal pngcairo size 1400,900 font "sans,11" noenhanced
set output "$png.partial"
set datafile separator ","
set multiplot layout 2,1 title "cardiosph turek-hron-fsi2 (Re 100, dp = D / 10, bar at twice the fluid's resolution)"
set size ratio -1
set xrange [-2:11]; set yrange [0:4.1]
set cbrange [-5:5]; set palette defined (-5 "#2166ac", 0 "#f7f7f7", 5 "#b2182b")
set cblabel "vorticity"
unset key
set title "end of the run"
plot "$dir/snapshot.csv" every ::1 using (\$1 == 0 ? \$2 : 1/0):3:5 with points pt 7 ps 0.35 lc palette, \
     "$dir/snapshot.csv" every ::1 using (\$1 == 1 ? \$2 : 1/0):3 with points pt 7 ps 0.3 lc rgb "black"
set size noratio
unset colorbox
set autoscale; set yrange [-1.2:1.2]
set title "bar tip y displacement"
set xlabel "t U / D"; set ylabel "dy / D"; set key left bottom horizontal
plot "$dir/observers.csv" every ::1 using 1:3 with lines lw 1.5 lc rgb "#1b9e77" title "cardiosph", \
     0.0123 + 0.806 with lines dt 2 lc rgb "black" title "Turek and Hron 2006: 0.0123 +- 0.806", \
     0.0123 - 0.806 with lines dt 2 lc rgb "black" notitle $extra
unset multiplot
GNUPLOT
mv "$png.partial" "$png"
echo "plot_fsi2: wrote $png"
