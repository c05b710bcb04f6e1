import json, collections
new = [json.loads(l) for l in open('results/baselines/families_s12/grid_planners.jsonl')]
olds = {'dstar_lite': ('results/baselines/dstar_s6/episodes.jsonl', 'dstar_lite'),
        'dwa_global': ('results/baselines/dwa_global_s7/families/episodes.jsonl', 'dwa_global_la06_kc06'),
        'apf': ('results/baselines/apf_dwa_s7/episodes.jsonl', None)}
for lab, (p, ol) in olds.items():
    rows = [json.loads(l) for l in open(p)]
    if ol is None:
        labs = collections.Counter(r['label'] for r in rows); ol = [l for l in labs if 'apf' in l][0]
    old = {r['world']: r for r in rows if r['label'] == ol}
    nw = {r['world']: r for r in new if r['label'] == lab}
    keys = set(old) & set(nw)
    eq = sum(all(old[k][f] == nw[k][f] for f in ('outcome', 'time_s', 'path_length_m', 'collisions')) for k in keys)
    oe = sum(old[k]['outcome'] == nw[k]['outcome'] for k in keys)
    print(lab, ol, len(keys), 'equal rows', eq, 'equal outcomes', oe, 'reached old', sum(old[k]['outcome']=='reached' for k in keys), 'new', sum(nw[k]['outcome']=='reached' for k in keys))
