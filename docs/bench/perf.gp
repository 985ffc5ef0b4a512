set datafile separator ','
set grid
set logscale xy
set key inside top left
set format x '10^{%T}'
files = 'png svg'
do for [f in files] {
  if (f eq 'png') { set terminal pngcairo size 1100,500 } else { set terminal svg size 1100,500 }
  set output 'perf.'.f
  set multiplot layout 1,2
  set xlabel 'triangles'
  set ylabel 'caustic pass (ms)'
  plot 'perf.csv' using ($2 == 256 ? $3 : 1/0):4 with points pointsize 1.3 title '256^2 px', 'perf.csv' using ($2 == 512 ? $3 : 1/0):4 with points pointsize 1.3 title '512^2 px', 'perf.csv' using ($2 == 1024 ? $3 : 1/0):4 with points pointsize 1.3 title '1024^2 px', 'perf.csv' using ($2 == 2048 ? $3 : 1/0):4 with points pointsize 1.3 title '2048^2 px'
  set xlabel 'pixels'
  set ylabel 'ms per frame (mesh 256^2)'
  plot 'perf.csv' using ($1 == 256 ? $2*$2 : 1/0):5 with linespoints title 'post', '' using ($1 == 256 ? $2*$2 : 1/0):6 with linespoints title 'RGBA read-back', '' using ($1 == 256 ? $2*$2 : 1/0):7 with linespoints title 'I420 convert + read-back'
  unset multiplot
}
