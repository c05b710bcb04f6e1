#!/bin/bash
# usage: screen.sh TREE OUTDIR -- C's new-contact episodes + bug2 office_2, time limit from gate_C rows
TREE=$(realpath $1); OUT=$2; mkdir -p $OUT; cd $TREE
for job in "office_2 bug2" "office_3 bug2" "office_11 bug2" "clutter_3 bug2" "clutter_7 bug2" "clutter_10 bug2" "clutter_18 bug2" "office_0 tangent_bug" "clutter_3 tangent_bug" "office_2 tangent_bug" "office_7 tangent_bug" "clutter_9 tangent_bug" "office_1 tangent_bug"; do
  set -- $job
  T=$(/work/venv/bin/python -c "import json;print([r['time_limit_s'] for r in map(json.loads,open('results/baselines/follow_s13/gate_C/families_after.jsonl')) if r['world']=='$1' and r['label']=='$2'][0])")
  env PYTHONPATH=$TREE /work/venv/bin/python -m nav_bench episode results/baselines/bugs_s6/worlds/$1.yaml --planner $2 --seed 0 --time-limit $T --json --plot $OUT/$1_$2.png > $OUT/$1_$2.json 2> $OUT/$1_$2.err
  echo "$1 $2 $(/work/venv/bin/python -c "import json;d=json.load(open('$OUT/$1_$2.json'));print({k:d.get(k) for k in ('outcome','stuck_reason','time_s','collisions','min_clearance_m','cpu_s')})" 2>&1)"
done
