#!/usr/bin/env python3
"""The GPU configurations of `hrpp simulate` (model/gpu/*.json): every key of the schema present
(the optional ones may be absent) with its type and a positive value (0 where it means none or
unbounded), no unknown keys, powers of two where the caches need them (line bytes, sector bytes,
sets = bytes / line_bytes / ways, warp size), and a `sources` entry for every number and switch
(docs/timing_model.md, "GPU configurations").

  gpu_configs_test.py ROOT        (ctest: sim.gpu_configs)
"""
import json
import pathlib
import sys

# The schema: key -> int, float (int or float accepted), bool, str, or a nested schema.
CACHE = {"bytes": int, "ways": int, "line_bytes": int, "hit_latency": int, "mshrs": int,
         "sector_bytes": int}
SCHEMA = {
    "name": str,
    "description": str,
    "clock_mhz": int,
    "units": int,
    "warps_per_unit": int,
    "warp_size": int,
    "l1": {**CACHE, "requests_per_cycle": int},
    "l2": {**CACHE, "bytes_per_cycle": int},
    "dram": {"latency": int, "bytes_per_cycle": float},
    "box": {"latency": int, "per_cycle": int},
    "triangle": {"latency": int, "per_cycle": int},
    "rt_unit": {"request_bytes": int, "triangle_records": bool, "triangle_bytes": int,
                "leaf_end_bytes": int, "launch_latency": int},
    "sources": dict,
}
OPTIONAL = {"l1.sector_bytes", "l2.sector_bytes", "rt_unit", "rt_unit.request_bytes",
            "rt_unit.triangle_records", "rt_unit.triangle_bytes", "rt_unit.leaf_end_bytes",
            "rt_unit.launch_latency"}
# Numbers whose 0 means none (a latency) or unbounded (a rate).
ZERO_OK = {"l1.hit_latency", "l2.hit_latency", "dram.latency", "box.per_cycle",
           "triangle.per_cycle", "rt_unit.leaf_end_bytes", "rt_unit.launch_latency"}
CONFIGS = ("mobile", "desktop", "micro21-sim")


def pow2(n: int) -> bool:
    return n > 0 and n & (n - 1) == 0


def check_fields(obj: dict, schema: dict, prefix: str, numbers: list[str], errors: list[str]):
    """Types and positive values of obj against schema; collects the dotted names of numbers."""
    for key in sorted(set(obj) - set(schema)):
        errors.append(f"unknown key '{prefix}{key}'")
    for key, kind in schema.items():
        name = prefix + key
        if key not in obj:
            if name not in OPTIONAL:
                errors.append(f"missing key '{name}'")
            continue
        value = obj[key]
        if isinstance(kind, dict):
            if not isinstance(value, dict):
                errors.append(f"'{name}' must be an object")
            else:
                check_fields(value, kind, name + ".", numbers, errors)
        elif kind is str:
            if not isinstance(value, str) or not value.strip():
                errors.append(f"'{name}' must be a non-empty string")
        elif kind is dict:
            if not isinstance(value, dict):
                errors.append(f"'{name}' must be an object")
        elif kind is bool:
            if not isinstance(value, bool):
                errors.append(f"'{name}' must be true or false")
            else:
                numbers.append(name)
        else:
            ok_types = (int,) if kind is int else (int, float)
            if isinstance(value, bool) or not isinstance(value, ok_types):
                errors.append(f"'{name}' must be {'an integer' if kind is int else 'a number'}")
            elif not (value > 0 or (value == 0 and name in ZERO_OK)):
                errors.append(f"'{name}' must be positive, not {value}")
            else:
                numbers.append(name)


def check_config(cfg: dict, stem: str) -> list[str]:
    errors: list[str] = []
    numbers: list[str] = []
    check_fields(cfg, SCHEMA, "", numbers, errors)
    if errors:
        return errors
    if cfg["name"] != stem:
        errors.append(f"name '{cfg['name']}' differs from the file name '{stem}'")
    if not pow2(cfg["warp_size"]):
        errors.append(f"warp_size {cfg['warp_size']} is not a power of two")
    for level in ("l1", "l2"):
        c = cfg[level]
        if not pow2(c["line_bytes"]):
            errors.append(f"{level}.line_bytes {c['line_bytes']} is not a power of two")
        if "sector_bytes" in c and not (pow2(c["sector_bytes"])
                                        and c["sector_bytes"] <= c["line_bytes"]):
            errors.append(f"{level}.sector_bytes {c['sector_bytes']} is not a power of two "
                          "no larger than the line")
        sets, rest = divmod(c["bytes"], c["line_bytes"] * c["ways"])
        if rest or not pow2(sets):
            errors.append(f"{level}: bytes / line_bytes / ways = "
                          f"{c['bytes'] / (c['line_bytes'] * c['ways'])} sets, not a power of two")
    sources = cfg["sources"]
    for name in numbers:
        text = sources.get(name)
        if not isinstance(text, str) or not text.strip():
            errors.append(f"no sources entry for '{name}'")
    for name in sorted(set(sources) - set(numbers)):
        errors.append(f"sources entry '{name}' names no number of the configuration")
    return errors


def main() -> int:
    root = pathlib.Path(sys.argv[1]) if len(sys.argv) > 1 else pathlib.Path(__file__).parents[2]
    failed = False
    for stem in CONFIGS:
        path = root / "model" / "gpu" / f"{stem}.json"
        try:
            cfg = json.loads(path.read_text())
        except (OSError, ValueError) as e:
            print(f"{path}: cannot read: {e}")
            failed = True
            continue
        errors = check_config(cfg, stem) if isinstance(cfg, dict) else ["not a JSON object"]
        for e in errors:
            print(f"{path}: {e}")
        failed |= bool(errors)
        if not errors:
            print(f"{path}: ok ({len(cfg['sources'])} numbers, each with a source)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
