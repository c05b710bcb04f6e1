#!/bin/bash
# usage: screen.sh TREE OUTDIR  -- replays the 5 follower endings one after the other
TREE=$1; OUT=$2; mkdir -p $OUT
cd $TREE
for job in "office_2 bug2 289.5" "office_11 bug2 289.5" "office_2 tangent_bug 289.5" "office_16 tangent_bug 289.5" "clutter_3 tangent_bug 300"; do
  set -- $job
  /usr/bin/time -f "%U" -o $OUT/$1_$2.cpu env PYTHONPATH=$TREE /work/venv/bin/python -m nav_bench episode results/baselines/bugs_s6/worlds/$1.yaml --planner $2 --seed 0 --time-limit $3 --json --plot $OUT/$1_$2.png > $OUT/$1_$2.json 2> $OUT/$1_$2.err
  echo "$1 $2 $(python3 -c "import json,sys;d=json.load(open('$OUT/$1_$2.json'));print({k:d.get(k) for k in ('outcome','stuck_reason','time_s','collisions','min_clearance_m','cpu_s')})" 2>&1) cpu=$(cat $OUT/$1_$2.cpu)"
done
