#!/usr/bin/python3
"""The forecast added to the alarm: is "IMMINENT or calibrated P >= p*" earlier than IMMINENT alone at no more false
alarms? (issue 29's lead goal; docs/BENCHMARKS.md "Forecast").

    scripts/forecast-lead-or-imminent.py FORECAST_DIR ALARMS_DIR

FORECAST_DIR: `rockwatch study ... --forecast --out FORECAST_DIR`; ALARMS_DIR: the same plan with `--alarms` instead
(its runs.csv has t_first_imminent_s). p* is chosen per record left out, on the other records' survivors, as the study
chooses its thresholds (the smallest p* on a 0.01 grid that flags no more survivors than IMMINENT flags there), with
the study's calibrated P (forecast.csv p_calibrated, itself fitted leaving the record out). Prints, for IMMINENT alone,
the calibrated P alone and the two together: (survivors flagged, survivors, collapses flagged before the collapse,
collapses, median lead [s]).
"""
import csv, sys, statistics as st, collections
fc, al = sys.argv[1], sys.argv[2]
runs = {int(r['run']): r for r in csv.DictReader(open(al + '/runs.csv'))}
F = collections.defaultdict(list)
for r in csv.DictReader(open(fc + '/forecast.csv')):
    F[int(r['run'])].append((float(r['t_s']), float(r['p_calibrated'])))
ids = sorted(F.keys() | {i for i, r in runs.items() if r['error'] == ''})
group = {i: runs[i]['record'] for i in ids}
coll = {i: runs[i]['collapsed'] == 'true' for i in ids}
tc = {i: float(runs[i]['t_collapse_s']) if runs[i]['t_collapse_s'] else None for i in ids}
ti = {i: float(runs[i]['t_first_imminent_s']) if runs[i]['t_first_imminent_s'] else None for i in ids}
maxp = {i: max((p for _, p in F[i]), default=0.0) for i in ids}
def first_cross(i, ps):
    for t, p in F[i]:
        if p >= ps - 1e-12: return t
    return None
def score(rule):
    leads, fa, nsurv, flagged, ncoll = [], 0, 0, 0, 0
    for g in sorted(set(group.values())):
        train = [i for i in ids if group[i] != g and not coll[i]]
        if rule == 'imminent':
            ps = None
        else:
            allowed = sum(1 for i in train if ti[i] is not None)
            ps = None
            for k in range(1, 101):
                cand = k / 100
                if rule == 'or':
                    n = sum(1 for i in train if ti[i] is not None or maxp[i] >= cand - 1e-12)
                else:
                    n = sum(1 for i in train if maxp[i] >= cand - 1e-12)
                if n <= allowed: ps = cand; break
        for i in ids:
            if group[i] != g: continue
            tf = None
            if rule in ('or', 'imminent'): tf = ti[i]
            if rule in ('or', 'p') and ps is not None:
                t2 = first_cross(i, ps)
                if t2 is not None and (tf is None or t2 < tf): tf = t2
            if coll[i]:
                ncoll += 1
                if tf is not None and tf < tc[i]: flagged += 1; leads.append(tc[i] - tf)
            else:
                nsurv += 1
                if tf is not None: fa += 1
    return fa, nsurv, flagged, ncoll, st.median(leads) if leads else None
for rule in ('imminent', 'p', 'or'):
    print(rule, score(rule))
