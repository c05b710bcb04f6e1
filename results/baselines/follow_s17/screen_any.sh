#!/bin/bash
# usage: screen_any.sh TREE OUT PLANNER WORLD... -- CLI episodes of generated family worlds (office_27,
# clutter_9, ...; seeds >= 20 are rep_fam's), seed 0, time limits from this folder's gate_A rows
HERE=$(dirname $(realpath $0)); TREE=$(realpath $1); mkdir -p $2; OUT=$(realpath $2); P=$3; shift 3
for w in "$@"; do
  s=families; [ ${w#*_} -ge 20 ] && s=rep_fam
  T=$(/work/venv/bin/python -c "import json;print([r['time_limit_s'] for r in map(json.loads,open('$HERE/gate_A/${s}_after.jsonl')) if r['world']=='$w' and r['label']=='$P'][0])")
  (cd $TREE && PYTHONPATH=$TREE /work/venv/bin/python -m nav_bench generate ${w%_*} --seed ${w#*_} -o $OUT/$w.yaml >/dev/null 2>&1
   PYTHONPATH=$TREE /work/venv/bin/python -m nav_bench episode $OUT/$w.yaml --planner $P --seed 0 --time-limit $T --json > $OUT/${w}_$P.json 2>/dev/null)
  echo "$P $w $(/work/venv/bin/python -c "import json;d=json.load(open('$OUT/${w}_$P.json'));print(d['outcome'],d.get('stuck_reason'),d['time_s'],'contacts',d['collisions'])")"
done
