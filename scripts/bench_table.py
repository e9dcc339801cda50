#!/usr/bin/env python3
"""The docs/benchmark.md tables (markdown) from wetdem_bench --json files: scripts/bench_table.py A.json [B.json ...]"""
import json,sys
rows=[]
for f in sys.argv[1:]:
  d=json.load(open(f))
  for r in d['runs']:
    t=r['traffic']; m=r['memory']; tm=r['timing']
    ri=r['rebuild_interval_steps']
    passes=', '.join('%s %.0f %%'%(p['name'],100*p['share']) for p in r['passes'][:3])
    rows.append('| %s | %s | %s | %s | %.3g | %.2g s (%.2g×) | %s | %d | %d | %.1f | %.0f | %.0f | %.1f %% | %s |'%(
      r['case'], r['variant'], f"{r['particles']:,}", f"{tm['steps']:,}", r['particle_steps_per_s'], tm['rotation_s'], tm['rotation_fraction_of_steady_start'],
      '-' if ri is None else '%.1f'%ri, r['contacts'], r['bridges'], r['entries_per_particle'], m['bytes_per_particle_at_measured_entries'],
      t['bytes_per_particle_step'], 100*t.get('fraction_of_roofline',0), passes))
print('| case | variant | particles | timed steps | p-steps/s | rotation before timing (of steady start) | rebuild | contacts | bridges | entr/p | B/p | B/p-st | roofl. | largest passes |')
print('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|')
print('\n'.join(rows))
# Ensembles (wetdem_bench --ensemble): aggregate particle-steps/s of k copies of a drum in one System.
ens=[]
for f in sys.argv[1:]:
  d=json.load(open(f))
  for r in d['runs']:
    for e in r.get('ensembles',[]):
      ens.append('| %s | %s | %s | %.3g | %d | %.3g | %.2f× |'%(d.get('device_name','?'), r['case'], f"{r['particles']:,}",
                 r['particle_steps_per_s'], e['runs'], e['particle_steps_per_s'], e['speedup_over_one_run']))
if ens:
  print('\n| device | drum | particles per run | one run (p-steps/s) | runs | ensemble (aggregate p-steps/s) | over one run |')
  print('|---|---|---|---|---|---|---|')
  print('\n'.join(ens))
