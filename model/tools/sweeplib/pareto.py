"""Pareto fronts: the non-dominated points, the baseline walk as a point, and the groups of rows
a front compares (scene, ray kind and query)."""

def pareto_front(points, minimize=(), maximize=()):
    """Indices of the points no other point dominates (at least as good in every objective and
    better in one). points: dicts (or sequences) indexed by the objective keys. Sorted by the
    first objective."""
    def key(p):
        return tuple(p[m] for m in minimize) + tuple(-p[m] for m in maximize)
    keys = [key(p) for p in points]
    front = []
    for i, ki in enumerate(keys):
        dominated = any(all(a <= b for a, b in zip(kj, ki)) and kj != ki
                        for j, kj in enumerate(keys) if j != i)
        if not dominated:
            front.append(i)
    return sorted(front, key=lambda i: keys[i])


def with_baselines(pts):
    """The points plus, per workload (spp), the baseline walk without a predictor: exact, at the
    baseline's cycles. A configuration slower than it is never worth building."""
    base = {}
    for p in pts:
        base.setdefault(p["spp"], p)
    out = list(pts)
    for spp, p in base.items():
        b = {n: "" for n in p}
        b.update({"scene": p["scene"], "kind": p["kind"], "spp": spp, "baseline": True,
                  "hrpp_cycles_per_ray": p["baseline_cycles_per_ray"],
                  "baseline_cycles_per_ray": p["baseline_cycles_per_ray"], "accuracy": 1.0,
                  "saved_cycles": 0.0})
        out.append(b)
    return out


def query(r):
    """Rows answer the same query when this matches: any-hit kinds, or every ray in mode anyhit
    (the study's hit-any column), against closest hits. Fronts compare like with like."""
    return "any-hit" if r["mode"] == "anyhit" or r["kind"] in ("shadow", "ao") else "closest-hit"


def groups(rows, by_query=False):
    out = {}
    for r in rows:
        key = (r["scene"], r["kind"]) + ((query(r),) if by_query else ())
        out.setdefault(key, []).append(r)
    return out
