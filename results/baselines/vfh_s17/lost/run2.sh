#!/bin/bash
# OUT=/tmp/s17vfhd/m; the G3 copy in /tmp/s17vfhd/g3 = this tree + ../candidate_G3_brake.patch + scratch_instrument.patch
# the brake on/off on the same noise streams (scratch copy with NB_RNG_PID)
OUT=${OUT:-/tmp/s17vfhd/m}; mkdir -p $OUT; cd /tmp/s17vfhd/g3
for ep in "clutter_0 1" "clutter_0 2" "office_11 1"; do set -- $ep; w=$1; s=$2
 for st in g3:ed70559597 d:e3e9c55d25 main:3e2d16e69e; do sn=${st%%:*}; pid=${st##*:}
  for cfg in brake:vfh_plus nobrake:vfh_plus:brake_speed=0; do cn=${cfg%%:*}; spec=${cfg#*:}
   o=$OUT/${w}_s${s}_${cn}_st${sn}
   NB_RNG_PID=$pid PYTHONPATH=$PWD /work/venv/bin/python -m nav_bench episode results/baselines/bugs_s6/worlds/$w.yaml --planner "$spec" --seed $s --json --trace $o.npz > $o.json 2>$o.err
   echo $w $s stream=$sn $cn $(python3 -c "import json;r=json.load(open('$o.json'));print(r['outcome'],r['time_s'],r['collisions'],r.get('stuck_reason'))")
  done
 done
done
