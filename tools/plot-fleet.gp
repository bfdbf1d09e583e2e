# gnuplot -e "out='docs/fleet-scale.png'" tools/plot-fleet.gp
# Cost per robot-step against fleet size, from docs/data/fleet-scale.dat.
if (!exists("out")) out = 'docs/fleet-scale.png'
set terminal pngcairo size 720,420 font ",10"
set output out
set logscale x
set xrange [70:14000]
set yrange [0:2]
set xlabel "robots (teams of 10)"
set ylabel "CPU per robot-step, us (one core)"
set title "tandem fleet: whole system in lockstep"
set key right bottom box opaque
set grid
plot 'docs/data/fleet-scale.dat' using 1:2 with linespoints pt 7 title "every robot in ODE (--rover-far ode)", \
     '' using 1:3 with linespoints pt 5 title "far robots kinematic, one rover host", \
     '' using 1:4 with points pt 9 ps 1.6 title "far robots kinematic, 4 rover hosts"
