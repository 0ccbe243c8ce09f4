"""The hardware's configurations and latencies: the loader of rtl/config/hrpp_configs.json
(rtl/config/README.md), for every script that needs them (rtl/syn/synth.py,
model/tools/results.py, tb/slang_lint.py) and for the generator rtl/config/hrpp_config.py, which
writes what the other languages read.

load() gives the configurations and latencies; config() one configuration; hrpp_top_params()
its top-level parameters, predict_options() / predict_args() the matching `hrpp predict` options.
"""
from __future__ import annotations

import json
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
JSON_PATH = ROOT / "rtl" / "config" / "hrpp_configs.json"

# Enumerations the configurations name: JSON value -> (SystemVerilog name, encoding, C++ name).
VARIANTS = {"faithful": ("HashFaithful", 0, "HashVariant::kFaithful"),
            "improved": ("HashImproved", 1, "HashVariant::kImproved")}
COMBINES = {"xor": ("CombineXor", 0, "CombineMode::kXor"),
            "concat": ("CombineConcat", 1, "CombineMode::kConcat")}
DIR_CODES = {"grid": ("DirGrid", 0, "DirCode::kGrid"),
             "oct": ("DirOct", 1, "DirCode::kOct")}
ENUMS = {"variant": VARIANTS, "combine": COMBINES, "dir_code": DIR_CODES}

# JSON field -> hrpp_top parameter, in hrpp_top's order.
PARAMS = [("variant", "Variant"), ("precision", "Precision"), ("exp_bits", "ExpBits"),
          ("origin_bits", "OriginBits"), ("dir_bits", "DirBits"), ("combine", "Combine"),
          ("dir_code", "DirCode"),
          ("sets", "NumSets"), ("ways", "NumWays"), ("nodes_per_entry", "NodesPerEntry"),
          ("node_id_width", "NodeIdWidth"), ("tag_bits", "TagWidth"), ("id_width", "IdWidth"),
          ("pred_fifo_depth", "PredFifoDepth"), ("skip_fifo_depth", "SkipFifoDepth"),
          ("update_queue_depth", "UpdateQueueDepth"),
          ("key_store_bram", "KeyStoreBram"), ("inject_fault", "InjectFault"),
          ("confidence_bits", "ConfBits"), ("issue_reg", "IssueReg"),
          ("key_store_reg", "KeyStoreReg")]
BOOLS = ("key_store_bram", "inject_fault", "issue_reg", "key_store_reg")
# Optional fields, with their value when absent. lanes: lookups and updates per cycle
# (docs/microarchitecture.md, "Lanes"); one lane is hrpp_top; 2 or 4 lanes are hrpp_lanes, which
# has hrpp_top's parameters and Lanes. dir_code: the improved hash's direction code (docs/hash.md).
# confidence_bits: a confidence bit per table way (0 or 1: docs/hash.md, "Confidence", with
# threshold 1; hrpp_top only). predict_kinds: which rays the RT unit offers the predictor ("all",
# or "any-hit": shadow and AO rays only, as MICRO 2021's unit does); the rtl-NAME preset's
# --predict-kinds (the RTL predicts whatever it is offered). key_store_reg: the block-RAM key
# store's read register (docs/microarchitecture.md, "Key store"; needs key_store_bram).
OPTIONAL_FIELDS = {"lanes": 1, "dir_code": "grid", "confidence_bits": 0, "predict_kinds": "all",
                   "issue_reg": False, "key_store_reg": False}
FIELDS = [f for f, _ in PARAMS if f not in OPTIONAL_FIELDS]
LATENCIES = ["hash_stages", "lookup_stages", "update_stages", "decision_latency"]


class ConfigError(Exception):
    pass


def _pow2(n: int) -> bool:
    return n >= 1 and n & (n - 1) == 0


def _check(name: str, c: dict, bank_depth: int) -> None:
    missing = [f for f in FIELDS if f not in c]
    extra = [f for f in c if f not in FIELDS and f not in OPTIONAL_FIELDS]
    if missing or extra:
        raise ConfigError(f"configuration {name}: missing {missing}, unknown {extra}")
    if c["variant"] not in VARIANTS:
        raise ConfigError(f"configuration {name}: variant must be one of {list(VARIANTS)}")
    if c["combine"] not in COMBINES:
        raise ConfigError(f"configuration {name}: combine must be one of {list(COMBINES)}")
    if c["dir_code"] not in DIR_CODES:
        raise ConfigError(f"configuration {name}: dir_code must be one of {list(DIR_CODES)}")
    if c["dir_code"] == "oct" and (c["variant"] != "improved" or not 1 <= c["dir_bits"] <= 8):
        raise ConfigError(f"configuration {name}: dir_code oct needs the improved variant and "
                          "dir_bits 1..8")
    for f in BOOLS:
        if not isinstance(c[f], bool):
            raise ConfigError(f"configuration {name}: {f} must be true or false")
    for f in FIELDS:
        if f not in (*ENUMS, *BOOLS) and (
                not isinstance(c[f], int) or isinstance(c[f], bool) or c[f] < 0):
            raise ConfigError(f"configuration {name}: {f} must be a non-negative integer")
    for f in ("sets", "pred_fifo_depth", "skip_fifo_depth", "update_queue_depth"):
        if not _pow2(c[f]) or c[f] < 2:
            raise ConfigError(f"configuration {name}: {f} must be a power of two >= 2")
    if c["lanes"] not in (1, 2, 4) or isinstance(c["lanes"], bool):
        raise ConfigError(f"configuration {name}: lanes must be 1, 2 or 4")
    if c["sets"] // c["lanes"] < 2:
        raise ConfigError(f"configuration {name}: sets / lanes must be at least 2 (sets per bank)")
    conf = c["confidence_bits"]
    if not isinstance(conf, int) or isinstance(conf, bool) or conf not in (0, 1):
        raise ConfigError(f"configuration {name}: confidence_bits must be 0 or 1, got {conf!r} "
                          "(the RTL drops a request identical to the one just before it only if "
                          "applying it twice equals applying it once: a demote of a 1-bit "
                          "counter; more bits are the golden model's only, hrpp predict "
                          "--confidence-bits)")
    if c["predict_kinds"] not in ("all", "any-hit"):
        raise ConfigError(f"configuration {name}: predict_kinds must be \"all\" or \"any-hit\"")
    if c["lanes"] != 1 and conf:
        raise ConfigError(f"configuration {name}: confidence_bits is not available with lanes > 1 "
                          "(hrpp_lanes has no confidence bits)")
    if c["lanes"] != 1 and c["key_store_bram"]:
        raise ConfigError(f"configuration {name}: key_store_bram is not available with lanes > 1 "
                          "(hrpp_lanes keeps each lane's key store in distributed RAM)")
    if c["lanes"] != 1 and c["sets"] > bank_depth:
        raise ConfigError(f"configuration {name}: more than {bank_depth} sets (the "
                          "table_bank_depth) is not available with lanes > 1 (hrpp_lanes)")
    if c["key_store_reg"] and not c["key_store_bram"]:
        raise ConfigError(f"configuration {name}: key_store_reg needs key_store_bram (it is the "
                          "block RAM's output register)")


def load(path: Path = JSON_PATH) -> dict:
    """{"latencies": {...} with the derived ones, "configurations": {name: {field: value}}}.
    A configuration {"base": NAME, ...} is that configuration with the fields it names changed."""
    try:
        raw = json.loads(Path(path).read_text())
    except (OSError, ValueError) as e:
        raise ConfigError(f"{path}: {e}")
    lat = dict(raw["latencies"])
    if sorted(lat) != sorted(LATENCIES) or not all(isinstance(v, int) and v >= 1
                                                  for v in lat.values()):
        raise ConfigError(f"{path}: latencies must be positive integers {LATENCIES}")
    # Derived (docs/microarchitecture.md, "Pipeline"): a ray accepted in cycle c is in the input
    # registers A in c+1, the hash stages, the key registers B (the table's read), the lookup
    # stages, and the prediction FIFO (pred_valid_o) prediction_latency cycles after c.
    lat["prediction_latency"] = 1 + lat["hash_stages"] + 1 + lat["lookup_stages"] + 1
    # A final outcome accepted in cycle t is in F0 in t+1, the update queue in t+2, then the
    # update stages (T0 .. W): W writes the table update_write_latency cycles after t.
    lat["update_write_latency"] = 2 + lat["update_stages"]
    # The first ray whose lookup (in B, 2 + hash_stages cycles after its acceptance) sees that
    # write is accepted update_landing cycles after the outcome (a lookup sees a write presented
    # in the cycle of its read).
    lat["update_landing"] = lat["update_write_latency"] - (2 + lat["hash_stages"])
    bank_depth = raw.get("table_bank_depth")
    if not isinstance(bank_depth, int) or isinstance(bank_depth, bool) or not _pow2(bank_depth) \
            or bank_depth < 2:
        raise ConfigError(f"{path}: table_bank_depth must be a power of two >= 2, got "
                          f"{bank_depth!r}")
    cfgs: dict[str, dict] = {}
    for name, c in raw["configurations"].items():
        if "base" in c:
            if c["base"] not in cfgs:
                raise ConfigError(f"configuration {name}: base {c['base']} is not defined above it")
            c = {**cfgs[c["base"]], **{k: v for k, v in c.items() if k != "base"}}
        c = {**OPTIONAL_FIELDS, **c}
        _check(name, c, bank_depth)
        cfgs[name] = c
    if "default" not in cfgs:
        raise ConfigError(f"{path}: no configuration named default")
    return {"latencies": lat, "table_bank_depth": bank_depth, "configurations": cfgs}


def latencies(c: dict, data: dict | None = None) -> dict:
    """The latencies of configuration c: the declared ones, and with a key store in block RAM
    (key_store_bram) one cycle more of decision, update write and update landing latency (its
    registered read: docs/microarchitecture.md, "Key store") and one more with its read register
    (key_store_reg), and with the table's issue register (issue_reg) one cycle more of update
    write and landing latency. A table of more sets per lane than table_bank_depth (RAM banks) has
    one lookup stage more (L3b): one cycle more of lookup and prediction latency."""
    data = data or load()
    lat = dict(data["latencies"])
    if c["sets"] // c["lanes"] > data["table_bank_depth"]:
        for n in ("lookup_stages", "prediction_latency"):
            lat[n] += 1
    k = int(c["key_store_bram"]) + int(c["key_store_reg"])
    for n in ("decision_latency", "update_write_latency", "update_landing"):
        lat[n] += k
    # The table's issue register (issue_reg): a request waits a cycle in I before T0.
    for n in ("update_write_latency", "update_landing"):
        lat[n] += int(c["issue_reg"])
    return lat


def config(name: str, data: dict | None = None) -> dict:
    cfgs = (data or load())["configurations"]
    if name not in cfgs:
        raise ConfigError(f"unknown configuration {name!r} (known: {', '.join(cfgs)})")
    return cfgs[name]


def hrpp_top_params(c: dict, enums: str = "name") -> dict[str, int | str]:
    """hrpp_top's parameters (one-bit ones as 1'bN). enums="name": the enumerations as
    hrpp_pkg::Name (slang, Yosys); "int": as their encodings, 1'bN (Verilator's -G takes no enum
    values: tb/hrpp_tb_top.sv casts)."""
    out: dict[str, int | str] = {}
    for f, p in PARAMS:
        v = c[f]
        if f in ENUMS:
            sv, code, _ = ENUMS[f][v]
            out[p] = f"hrpp_pkg::{sv}" if enums == "name" else f"1'b{code}"
        elif f in BOOLS:
            out[p] = f"1'b{int(v)}"
        else:
            out[p] = int(v)
    return out


def top_module(c: dict) -> str:
    """The RTL top of a configuration: hrpp_top (one lane) or hrpp_lanes (2 or 4 lanes)."""
    return "hrpp_top" if c["lanes"] == 1 else "hrpp_lanes"


def top_params(c: dict, enums: str = "name") -> dict[str, int | str]:
    """The parameters of top_module(c) (and of tb/hrpp_tb_top.sv): hrpp_top's, and Lanes for more
    than one lane."""
    out = hrpp_top_params(c, enums)
    if c["lanes"] != 1:
        out["Lanes"] = int(c["lanes"])
    return out


def predict_options(c: dict, parts: tuple[str, ...] = ("hash", "table")) -> dict[str, str]:
    """The `hrpp predict` options (without --) of a configuration's hash and/or table."""
    o: dict[str, str] = {}
    if "hash" in parts:
        o["hash"] = c["variant"]
        if c["variant"] == "faithful":
            o["precision"], o["exp-bits"] = str(c["precision"]), str(c["exp_bits"])
        else:
            o["origin-bits"], o["dir-bits"] = str(c["origin_bits"]), str(c["dir_bits"])
            if c["dir_code"] != "grid":  # the default: the other configurations' options as before
                o["dir-code"] = c["dir_code"]
        o["combine"] = c["combine"]
    if "table" in parts:
        o["table"] = f"{c['sets']}x{c['ways']}"
        o["nodes-per-entry"] = str(c["nodes_per_entry"])
        o["tag-bits"] = str(c["tag_bits"])
        if c.get("confidence_bits", 0):  # only when set: every other configuration's as before
            o["confidence-bits"] = str(c["confidence_bits"])
            o["confidence-threshold"] = "1"
    if "kinds" in parts and c.get("predict_kinds", "all") != "all":
        o["predict-kinds"] = c["predict_kinds"]
    return o


def predict_args(c: dict, parts: tuple[str, ...] = ("hash", "table")) -> list[str]:
    return [x for k, v in predict_options(c, parts).items() for x in (f"--{k}", v)]


def describe(c: dict) -> str:
    h = (f"improved o{c['origin_bits']}/d{c['dir_bits']}" if c["variant"] == "improved"
         else f"faithful P={c['precision']} E={c['exp_bits']}")
    if c.get("dir_code", "grid") != "grid":
        h += f" {c['dir_code']}"
    lanes = f", {c['lanes']} lanes" if c.get("lanes", 1) != 1 else ""
    conf = ", confidence bit" if c.get("confidence_bits", 0) else ""
    kinds = ", any-hit rays only" if c.get("predict_kinds", "all") != "all" else ""
    return (f"{c['sets']}x{c['ways']}x{c['nodes_per_entry']}, tag {c['tag_bits']}, {h} "
            f"{c['combine']}{lanes}{conf}{kinds}")
