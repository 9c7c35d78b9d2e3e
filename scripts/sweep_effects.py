#!/usr/bin/env python3
"""The physics and timing effects (sim/lwr/README.md) against every shipped
scene's key metrics: one `tactile_sim run` per scene and setting, one
markdown-ish row each (scene | setting | exit code | status | rtf | metrics).

  /usr/bin/python3 scripts/sweep_effects.py [OUTDIR] [--set KEY=VALUE ...]
  e.g. --set fidelity=dynamics for the dynamic arm.
"""
import json, subprocess, sys, os
ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
BIN = os.environ.get('TACTILE_SIM', ROOT + '/build/bin/tactile_sim')
SCENES={
 "edge_exploration": ["alignment_time_s","path_length_m","force_true_mean_n","force_true_rms_error_n","contact_lost_count"],
 "bent_bar": ["force_true_mean_n","force_true_rms_error_n","slide_speed_mps","force_true_max_n","force_true_in_band_fraction"],
 "co_manipulation": ["dzmp_recovery_time_s","force_true_mean_n","translation_x_m","dzmp_final_m","tray_angle_max_deg"],
 "sphere_table": ["force_true_mean_n","force_true_rms_error_n"],
}
SETTINGS=[
 ("off", []),
 ("mu0.5", ["effects.friction_mu=0.5"]),
 ("mu1.0", ["effects.friction_mu=1.0"]),
 ("fri1ms", ["effects.fri_delay_s=0.001"]),
 ("fri2ms", ["effects.fri_delay_s=0.002"]),
 ("krc2ms", ["effects.krc_cycle_s=0.002"]),
 ("fri2+krc2", ["effects.fri_delay_s=0.002","effects.krc_cycle_s=0.002"]),
 ("all(mu0.5,fri2,krc2)", ["effects.friction_mu=0.5","effects.fri_delay_s=0.002","effects.krc_cycle_s=0.002"]),
 ("all(mu1.0,fri2,krc2)", ["effects.friction_mu=1.0","effects.fri_delay_s=0.002","effects.krc_cycle_s=0.002"]),
]
args_in = sys.argv[1:]
outdir = '/tmp/sweep_effects'
if args_in and not args_in[0].startswith('--'):
    outdir = args_in.pop(0)
extra = [a for a in args_in if a != '--set']  # KEY=VALUE overrides for every run
os.makedirs(outdir, exist_ok=True)
for sc, keys in SCENES.items():
    for name, sets in SETTINGS:
        d=f'{outdir}/run_{sc}_{name}{"_".join(extra).replace("=","").replace("-","")}'
        args=[BIN,'run',f'{ROOT}/sim/scenes/{sc}.yaml','--no-plots','--out',d]
        for s in sets+[e for e in extra]: args+=['--set',s]
        p=subprocess.run(args,capture_output=True,text=True)
        try: j=json.load(open(d+'/summary.json'))
        except Exception: j={}
        row=[sc,name,str(p.returncode),j.get('status','?'),'%.0f'%j.get('real_time_factor',0)]+[('%.4g'%j[k]) if isinstance(j.get(k),(int,float)) else str(j.get(k)) for k in keys]
        print(' | '.join(row), flush=True)
