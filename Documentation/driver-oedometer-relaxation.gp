# Figure of Documentation/driver-oedometer-relaxation.md from the default fast case:
#   build/bin/OedometerRelaxation --output out
#   gnuplot -e "rec='out/OedometerRelaxation.recording.csv'" Documentation/driver-oedometer-relaxation.gp
if (!exists("rec")) rec = 'out/OedometerRelaxation.recording.csv'
if (!exists("png")) png = 'Documentation/driver-oedometer-relaxation.png'
set terminal pngcairo size 1100,420 font ",10"
set output png
set datafile separator ","
set datafile commentschars "#"
set key autotitle columnhead
set multiplot layout 1,2
set xlabel "lab time (s)"
set ylabel "stress (kPa)"
set key top right
plot rec using 1:($5/1000) with lines lw 2 title "axial (piston)", \
     rec using 1:($6/1000) with lines title "bottom", \
     rec using 1:($7/1000) with lines title "lateral"
set xlabel "axial strain"
set ylabel "axial stress (kPa)"
unset key
plot rec using 4:($5/1000) with lines lw 2
unset multiplot
