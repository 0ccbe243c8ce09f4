`default_nettype none
// Formal harness of hrpp_pred_table (docs/verification.md) on a small configuration: 2 sets x
// 2 ways x K = 2 node ids of 2 bits, 2-bit tags. The RAM model returns inverted data on a read of
// the word being written (HRPP_SIM_RW_GARBAGE), so a design relying on read-during-write fails.
//
// The harness keeps an abstract table, updated by the golden model's rule (docs/hash.md,
// "Predictor table"; model/src/predictor/pred_table.cc) in the cycle the RTL writes the update
// (W, UpdateStages cycles after the request is accepted). Checked on every cycle after the reset
// clear, on both RAM copies: the ages of a set are a permutation of 0..W-1, no two valid ways of
// a set hold the same tag (at most one matches a tag), no count exceeds K, and every set equals
// the abstract one (valid bits and ages; tag, count and the first `count` node ids of valid
// ways). A lookup returns what the abstract table holds after the writes of its read's cycle
// (the same-cycle write is forwarded): its count and first `count` node ids, four cycles later.
// ConfBits = 1 (tasks *_conf): every way's confidence bit too (docs/hash.md, "Confidence", C = 1,
// T = 1): requests are updates or demotes (free), the abstract table applies the golden rule of
// each (a merged request too), the bits of valid ways must equal it, and a lookup of a way whose
// bit is 0 returns no prediction. The one rule the harness takes from the design: a request of
// the set and tag of the newer of the requests of its set accepted in the two previous cycles (the
// table's interlock window) merges into it when it is a demote, or that request's last update (its
// own or the last merged into it) is none, or has the request's node: the abstract table applies
// it by the golden rule right after that request (and those merged before it), in that request's
// W cycle, instead of in its own. With the issue register (IssueReg = 1) the request judged is
// the one in I, taken from the input when tbl_wr_ready_o was high; the harness takes from the
// design when it leaves I (dut.wr_go), and checks that I holds that request and that I's
// compares, made a cycle early, are those of the request against T0 and T1.
module pred_table_formal
  import hrpp_pkg::*;
#(
  parameter int unsigned NumSets = 2,
  parameter int unsigned NumWays = 2,
  parameter int unsigned NodesPerEntry = 2,
  parameter int unsigned NodeIdWidth = 2,
  parameter int unsigned TagWidth = 2,
  parameter int unsigned ConfBits = 0,
  parameter int unsigned RamBankDepth = 2048,  // tasks *_banks: 2 sets per RAM bank
  parameter bit PipeCheck = 1'b0,  // task prove_conf: assert Pipe_A (below)
  parameter bit IssueReg = DefaultIssueReg,  // tasks *_noreg: 0 (the table without I)
  localparam int unsigned IdxWidth = $clog2(NumSets),
  localparam int unsigned CountWidth = $clog2(NodesPerEntry + 1),
  localparam int unsigned AgeWidth = $clog2(NumWays)
) (
  input logic                   clk_i,
  input logic                   lk_valid_i,
  input logic [IdxWidth-1:0]    lk_idx_i,
  input logic [TagWidth-1:0]    lk_tag_i,
  input logic                   tbl_wr_valid_i,
  input logic [IdxWidth-1:0]    tbl_wr_idx_i,
  input logic [TagWidth-1:0]    tbl_wr_tag_i,
  input logic [NodeIdWidth-1:0] tbl_wr_node_i,
  input logic                   tbl_wr_demote_i
);
  logic init_q = 1'b1;
  always_ff @(posedge clk_i) init_q <= 1'b0;
  logic rst_ni;
  assign rst_ni = !init_q;

  logic                                      init_done_o, lk_valid_o, tbl_wr_ready_o;
  logic [CountWidth-1:0]                     lk_count_o;
  logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes_o;

  hrpp_pred_table #(
    .NumSets(NumSets), .NumWays(NumWays), .NodesPerEntry(NodesPerEntry),
    .NodeIdWidth(NodeIdWidth), .TagWidth(TagWidth), .ConfBits(ConfBits),
    .RamBankDepth(RamBankDepth), .IssueReg(IssueReg)
  ) dut (.*);

  // Without confidence bits there are no demotes (hrpp_top ties the input to 0).
  always_comb if (ConfBits == 0) assume (!tbl_wr_demote_i);

  // Lookups and update requests start once the reset clear is over (hrpp_top accepts rays, and
  // its skip controller messages, only then).
  always_comb if (rst_ni && !init_done_o) assume (!lk_valid_i && !tbl_wr_valid_i);

  // The table's row layout in its RAM word (as in hrpp_pred_table), without the confidence bits,
  // which follow it in the word with ConfBits = 1 (one per way, way 0 first).
  typedef struct packed {
    logic                                      valid;
    logic [TagWidth-1:0]                       tag;
    logic [CountWidth-1:0]                     count;
    logic [NodesPerEntry-1:0][NodeIdWidth-1:0] nodes;
    logic [AgeWidth-1:0]                       age;
  } way_t;
  typedef way_t [NumWays-1:0] row_t;
  typedef row_t [NumSets-1:0] table_t;
  typedef logic [NumWays-1:0] conf_t;  // a set's confidence bits
  typedef conf_t [NumSets-1:0] conf_table_t;
  localparam int unsigned BaseRowWidth = $bits(row_t);
  localparam int unsigned RamWordWidth = BaseRowWidth + ConfBits * NumWays;

  // ---------------------------------------------------------------------------------------------
  // The golden update rule, written out plainly
  // ---------------------------------------------------------------------------------------------
  // The confidence bit an update leaves (C = 1): 1 when the tag's way held the node, else 0.
  function automatic logic golden_update_conf(row_t r, logic [TagWidth-1:0] tag,
                                              logic [NodeIdWidth-1:0] node);
    logic present;
    present = 1'b0;
    for (int i = 0; i < NumWays; i++)
      if (r[i].valid && r[i].tag == tag)
        for (int k = 0; k < NodesPerEntry; k++)
          if (k < int'(r[i].count) && r[i].nodes[k] == node) present = 1'b1;
    return present;
  endfunction
  // The way an update writes (the tag's, else the victim), as golden_update picks it.
  function automatic int golden_update_way(row_t r, logic [TagWidth-1:0] tag);
    int sel;
    sel = -1;
    for (int i = 0; i < NumWays; i++)
      if (sel < 0 && r[i].valid && r[i].tag == tag) sel = i;
    for (int i = 0; i < NumWays; i++)
      if (sel < 0 && !r[i].valid) sel = i;
    for (int i = 0; i < NumWays; i++)
      if (sel < 0 && r[i].age == AgeWidth'(NumWays - 1)) sel = i;
    return sel;
  endfunction

  function automatic row_t golden_update(row_t r, logic [TagWidth-1:0] tag,
                                         logic [NodeIdWidth-1:0] node);
    int   sel, pos, found;
    way_t w;
    logic [AgeWidth-1:0] old_age;
    sel = -1;
    for (int i = 0; i < NumWays; i++)  // the way holding the tag
      if (sel < 0 && r[i].valid && r[i].tag == tag) sel = i;
    if (sel < 0) begin  // a victim: the lowest-numbered invalid way, else the oldest
      for (int i = 0; i < NumWays; i++)
        if (sel < 0 && !r[i].valid) sel = i;
      for (int i = 0; i < NumWays; i++)
        if (sel < 0 && r[i].age == AgeWidth'(NumWays - 1)) sel = i;
      r[sel].valid = 1'b1;
      r[sel].tag = tag;
      r[sel].count = '0;
      r[sel].nodes = '0;
    end
    w = r[sel];
    // the node to the front: from its position if present, else inserted (the last one drops)
    found = -1;
    for (int i = 0; i < NodesPerEntry; i++)
      if (found < 0 && i < int'(w.count) && w.nodes[i] == node) found = i;
    pos = found >= 0 ? found : (int'(w.count) < NodesPerEntry ? int'(w.count) : NodesPerEntry - 1);
    for (int i = NodesPerEntry - 1; i >= 1; i--)
      if (i <= pos) w.nodes[i] = w.nodes[i-1];
    w.nodes[0] = node;
    if (found < 0 && int'(w.count) < NodesPerEntry) w.count = w.count + 1'b1;
    // ages: the younger ways get one older, the updated way is the youngest
    old_age = r[sel].age;
    for (int i = 0; i < NumWays; i++)
      if (r[i].age < old_age) r[i].age = r[i].age + 1'b1;
    w.age = '0;
    r[sel] = w;
    return r;
  endfunction

  // Equal as the golden model sees it: valid bits and ages; tags, counts, the first `count`
  // node ids and the confidence bits of valid ways.
  function automatic logic same_row(row_t a, conf_t ac, row_t b, conf_t bc);
    logic ok;
    ok = 1'b1;
    for (int w = 0; w < NumWays; w++) begin
      ok &= a[w].valid == b[w].valid && a[w].age == b[w].age;
      if (a[w].valid) begin
        ok &= a[w].tag == b[w].tag && a[w].count == b[w].count && ac[w] == bc[w];
        for (int i = 0; i < NodesPerEntry; i++)
          if (i < int'(a[w].count)) ok &= a[w].nodes[i] == b[w].nodes[i];
      end
    end
    return ok;
  endfunction

  function automatic logic row_invariants(row_t r);
    logic ok;
    ok = 1'b1;
    for (int w = 0; w < NumWays; w++) begin
      ok &= int'(r[w].count) <= NodesPerEntry;                        // count <= K
      for (int v = w + 1; v < NumWays; v++) begin
        ok &= r[w].age != r[v].age;                                   // ages: a permutation
        ok &= !(r[w].valid && r[v].valid && r[w].tag == r[v].tag);    // one way per tag
      end
      ok &= int'(r[w].age) < NumWays;
    end
    return ok;
  endfunction

  // ---------------------------------------------------------------------------------------------
  // The abstract table, updated in W's cycle
  // ---------------------------------------------------------------------------------------------
  typedef struct packed {
    logic                   valid;
    logic [IdxWidth-1:0]    idx;
    logic [TagWidth-1:0]    tag;
    logic [NodeIdWidth-1:0] node;
    logic                   demote;
    // ConfBits = 1: the requests merged into this one, in order (at most one per cycle in T0, T1)
    logic [1:0]                  m_valid;
    logic [1:0][NodeIdWidth-1:0] m_node;
    logic [1:0]                  m_demote;
  } req_t;
  req_t [UpdateStages-1:0] req_q;  // [UpdateStages-1]: the request in W
  table_t      model_q, model_next;
  conf_table_t mconf_q, mconf_next;  // the abstract table's confidence bits
  row_t        init;
  req_t        wreq;
  row_t        mrow;  // the set's row before each application of the golden update rule
  logic [NodeIdWidth-1:0] knode;  // the node of the request applied

  always_comb begin
    init = '0;
    for (int w = 0; w < NumWays; w++) init[w].age = AgeWidth'(w);
    model_next = model_q;
    mconf_next = mconf_q;
    wreq = req_q[UpdateStages-1];
    // the request, then the requests merged into it, each by the golden rule
    for (int k = 0; k < 3; k++) if (wreq.valid && (k == 0 || wreq.m_valid[k-1])) begin
      mrow = model_next[wreq.idx];
      knode = k == 0 ? wreq.node : wreq.m_node[k-1];
      if (k == 0 ? wreq.demote : wreq.m_demote[k-1]) begin  // the tag's way's bit cleared
        for (int w = 0; w < NumWays; w++)
          if (mrow[w].valid && mrow[w].tag == wreq.tag) mconf_next[wreq.idx][w] = 1'b0;
      end else begin
        model_next[wreq.idx] = golden_update(mrow, wreq.tag, knode);
        mconf_next[wreq.idx][golden_update_way(mrow, wreq.tag)] =
            ConfBits > 0 && golden_update_conf(mrow, wreq.tag, knode);
      end
    end
  end

  // The merge rule (ConfBits = 1): the newer accepted request of the set in the previous two
  // cycles (req_q[0], else req_q[1]; merged ones are not requests of their own) and whether the
  // request now accepted merges into it (its last update: the last merged, else its own).
  function automatic logic merges(req_t r, logic [TagWidth-1:0] tag,
                                  logic [NodeIdWidth-1:0] node, logic demote);
    logic                   last_demote;
    logic [NodeIdWidth-1:0] last_node;
    last_demote = r.demote;
    last_node = r.node;
    for (int k = 0; k < 2; k++)
      if (r.m_valid[k] && !r.m_demote[k]) begin
        last_demote = 1'b0;
        last_node = r.m_node[k];
      end
    return r.tag == tag && (demote || last_demote || last_node == node);
  endfunction
  // The request the table's interlock judges: the input, or with IssueReg the harness's copy of
  // I (the input taken when tbl_wr_ready_o was high); it leaves (issued or merged) when the
  // design's wr_go says so.
  typedef struct packed {
    logic                   valid;
    logic [IdxWidth-1:0]    idx;
    logic [TagWidth-1:0]    tag;
    logic [NodeIdWidth-1:0] node;
    logic                   demote;
  } jreq_t;
  jreq_t in_req, ai_q, jr;
  logic  j_go;
  assign in_req = '{tbl_wr_valid_i, tbl_wr_idx_i, tbl_wr_tag_i, tbl_wr_node_i, tbl_wr_demote_i};
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) ai_q <= '0;
    else if (tbl_wr_ready_o) ai_q <= in_req;
  end
  assign jr   = IssueReg ? ai_q : in_req;
  assign j_go = jr.valid && dut.wr_go;
  function automatic req_t with_merged(req_t r);
    req_t m;
    m = r;
    if (r.m_valid[0]) begin
      m.m_valid[1] = 1'b1;
      m.m_node[1] = jr.node;
      m.m_demote[1] = jr.demote;
    end else begin
      m.m_valid[0] = 1'b1;
      m.m_node[0] = jr.node;
      m.m_demote[0] = jr.demote;
    end
    return m;
  endfunction
  logic merge_new, merge_0;
  always_comb begin
    merge_0 = req_q[0].valid && req_q[0].idx == jr.idx;
    merge_new = merge_0 ? merges(req_q[0], jr.tag, jr.node, jr.demote)
                        : req_q[1].valid && req_q[1].idx == jr.idx &&
                          merges(req_q[1], jr.tag, jr.node, jr.demote);
    merge_new &= ConfBits > 0 && j_go;
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      req_q <= '0;
      for (int s = 0; s < NumSets; s++) model_q[s] <= init;
      mconf_q <= '0;
    end else begin
      req_q <= {req_q[UpdateStages-2:0],
                req_t'{j_go && !merge_new, jr.idx, jr.tag, jr.node, jr.demote, 2'b00, '0,
                       2'b00}};
      if (merge_new && merge_0) req_q[1] <= with_merged(req_q[0]);
      if (merge_new && !merge_0) req_q[2] <= with_merged(req_q[1]);
      model_q <= model_next;
      mconf_q <= mconf_next;
    end
  end

  // Lookups: the abstract table's answer (after the writes of the read's cycle), the lookup
  // latency on (four cycles; five with RAM banks).
  localparam int unsigned LkLat = lookup_latency(NumSets, RamBankDepth);
  logic [LkLat-1:0]                                     lk_q;
  logic [LkLat-1:0][CountWidth-1:0]                     exp_count_q;
  logic [LkLat-1:0][NodesPerEntry-1:0][NodeIdWidth-1:0] exp_nodes_q;
  logic [CountWidth-1:0]                     exp_count;
  logic [NodesPerEntry-1:0][NodeIdWidth-1:0] exp_nodes;
  always_comb begin
    exp_count = '0;
    exp_nodes = '0;
    for (int w = 0; w < NumWays; w++)
      if (model_next[lk_idx_i][w].valid && model_next[lk_idx_i][w].tag == lk_tag_i &&
          (ConfBits == 0 || mconf_next[lk_idx_i][w])) begin
        exp_count = model_next[lk_idx_i][w].count;
        exp_nodes = model_next[lk_idx_i][w].nodes;
      end
  end
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      lk_q        <= '0;
      exp_count_q <= '0;
      exp_nodes_q <= '0;
    end else begin
      lk_q        <= {lk_q[LkLat-2:0], lk_valid_i};
      exp_count_q <= {exp_count_q[LkLat-2:0], exp_count};
      exp_nodes_q <= {exp_nodes_q[LkLat-2:0], exp_nodes};
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Checks
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned L = LkLat - 1;
  logic inv_ok, model_ok, nodes_ok;
  // A RAM word's row (without the confidence bits) and its confidence bits (0 without them).
  function automatic row_t ram_row(logic [RamWordWidth-1:0] d);
    return row_t'(d[BaseRowWidth-1:0]);
  endfunction
  function automatic conf_t ram_conf(logic [RamWordWidth-1:0] d);
    return ConfBits > 0 ? conf_t'(d >> BaseRowWidth) : '0;
  endfunction
  // Each copy's words, set by set (set s in RAM bank s / BankDepth, as in hrpp_pred_table).
  localparam int unsigned RamBanks = NumSets > RamBankDepth ? NumSets / RamBankDepth : 1;
  localparam int unsigned BankDepth = NumSets / RamBanks;
  logic [NumSets-1:0][RamWordWidth-1:0] lk_mem, up_mem;
  for (genvar b = 0; b < RamBanks; b++) begin : gen_bank
    for (genvar i = 0; i < BankDepth; i++) begin : gen_set
      assign lk_mem[b * BankDepth + i] = dut.gen_ram_bank[b].u_lookup_ram.mem_q[i];
      assign up_mem[b * BankDepth + i] = dut.gen_ram_bank[b].u_update_ram.mem_q[i];
    end
  end
  always_comb begin
    inv_ok = 1'b1;
    model_ok = 1'b1;
    for (int s = 0; s < NumSets; s++) begin
      inv_ok &= row_invariants(ram_row(lk_mem[s])) && row_invariants(ram_row(up_mem[s]));
      model_ok &= same_row(model_q[s], mconf_q[s], ram_row(lk_mem[s]), ram_conf(lk_mem[s])) &&
                  same_row(model_q[s], mconf_q[s], ram_row(up_mem[s]), ram_conf(up_mem[s]));
    end
    nodes_ok = 1'b1;
    for (int i = 0; i < NodesPerEntry; i++)
      if (i < int'(exp_count_q[L])) nodes_ok &= lk_nodes_o[i] == exp_nodes_q[L][i];
  end

  // With ConfBits = 1, the update pipeline's stages carry the harness's requests: what the RTL's
  // stage holds for a request and the requests merged into it (a demote, else the last update's
  // node, and whether the merges fixed the bit, to what). An inductive strengthening (k-induction
  // starts from any state): a pipeline out of step with the abstract requests is unreachable.
  // It restates the design's merge encoding, so it is asserted in prove_conf only: in the bmc
  // runs (quick_conf, the planted bugs) Model_A and the lookups alone judge the design.
  typedef struct packed {
    logic                   valid;
    logic [IdxWidth-1:0]    idx;
    logic [TagWidth-1:0]    tag;
    logic [NodeIdWidth-1:0] node;  // the last update's (a demote: no node)
    logic                   demote, ovr, ovr_bit;
  } pipe_t;
  function automatic pipe_t pipe_view(req_t r);
    pipe_t p;
    p = '{r.valid, r.idx, r.tag, r.node, r.demote, 1'b0, 1'b0};
    for (int k = 0; k < 2; k++)
      if (r.m_valid[k]) begin
        if (r.m_demote[k]) begin  // behind a demote: nothing; behind an update: its bit 0
          if (!p.demote) {p.ovr, p.ovr_bit} = 2'b10;
        end else if (p.demote) begin  // an update behind a demote: the update
          p.demote = 1'b0;
          p.node = r.m_node[k];
          {p.ovr, p.ovr_bit} = 2'b00;
        end else begin  // the same update again: its bit 1
          {p.ovr, p.ovr_bit} = 2'b11;
        end
      end
    return p;
  endfunction
  function automatic logic same_pipe(pipe_t a, pipe_t b);
    return a.valid == b.valid &&
           (!a.valid || (a.idx == b.idx && a.tag == b.tag && a.demote == b.demote &&
                         (a.demote || a.node == b.node) && a.ovr == b.ovr &&
                         a.ovr_bit == b.ovr_bit));
  endfunction
  logic pipe_ok;
  always_comb begin
    pipe_ok = same_pipe(pipe_view(req_q[0]), pipe_t'{dut.t0_q.valid, dut.t0_q.idx, dut.t0_q.tag,
                            dut.t0_q.node, dut.t0_q.demote, dut.t0_q.ovr, dut.t0_q.ovr_bit}) &&
              same_pipe(pipe_view(req_q[1]), pipe_t'{dut.t1_q.valid, dut.t1_q.idx, dut.t1_q.tag,
                            dut.t1_q.node, dut.t1_q.demote, dut.t1_q.ovr, dut.t1_q.ovr_bit}) &&
              same_pipe(pipe_view(req_q[2]), pipe_t'{dut.t2_q.req.valid, dut.t2_q.req.idx,
                            dut.t2_q.req.tag, dut.t2_q.req.node, dut.t2_q.req.demote,
                            dut.t2_q.req.ovr, dut.t2_q.req.ovr_bit}) &&
              same_pipe(pipe_view(req_q[3]), pipe_t'{dut.c1_q.req.valid, dut.c1_q.req.idx,
                            dut.c1_q.req.tag, dut.c1_q.req.node, dut.c1_q.req.demote,
                            dut.c1_q.req.ovr, dut.c1_q.req.ovr_bit}) &&
              same_pipe(pipe_view(req_q[4]), pipe_t'{dut.c2_q.req.valid, dut.c2_q.req.idx,
                            dut.c2_q.req.tag, dut.c2_q.req.node, dut.c2_q.req.demote,
                            dut.c2_q.req.ovr, dut.c2_q.req.ovr_bit}) &&
              req_q[5].valid == dut.c3_q.valid &&
              (!req_q[5].valid || (req_q[5].idx == dut.c3_q.idx &&
                                   pipe_view(req_q[5]).demote == dut.c3_q.demote &&
                                   pipe_view(req_q[5]).ovr == dut.c3_q.ovr &&
                                   pipe_view(req_q[5]).ovr_bit == dut.c3_q.ovr_bit)) &&
              req_q[6].valid == dut.w_q.valid && (!req_q[6].valid || req_q[6].idx == dut.w_q.idx);
  end

  // IssueReg: I holds the harness's request, and its compares are those against T0 and T1 now.
  logic issue_ok;
  if (IssueReg) begin : gen_issue_check
    function automatic logic key_eq(logic [TagWidth-1:0] tag, logic [NodeIdWidth-1:0] node,
                                    logic demote);
      return ai_q.tag == tag && ((ConfBits > 0 && ai_q.demote) || demote || ai_q.node == node);
    endfunction
    always_comb begin
      issue_ok = dut.gen_issue_reg.i_q.valid == ai_q.valid;
      if (ai_q.valid) begin
        issue_ok &= dut.gen_issue_reg.i_q.idx == ai_q.idx && dut.gen_issue_reg.i_q.tag == ai_q.tag
                    && dut.gen_issue_reg.i_q.node == ai_q.node &&
                    dut.gen_issue_reg.i_q.demote == (ConfBits > 0 && ai_q.demote);
        issue_ok &= dut.gen_issue_reg.i_cmp_q.same_t0 ==
                    (dut.t0_q.valid && dut.t0_q.idx == ai_q.idx);
        issue_ok &= dut.gen_issue_reg.i_cmp_q.same_t1 ==
                    (dut.t1_q.valid && dut.t1_q.idx == ai_q.idx);
        if (dut.gen_issue_reg.i_cmp_q.same_t0)
          issue_ok &= dut.gen_issue_reg.i_cmp_q.as_t0 ==
                      key_eq(dut.t0_q.tag, dut.t0_q.node, dut.t0_q.demote);
        if (dut.gen_issue_reg.i_cmp_q.same_t1)
          issue_ok &= dut.gen_issue_reg.i_cmp_q.as_t1 ==
                      key_eq(dut.t1_q.tag, dut.t1_q.node, dut.t1_q.demote);
      end
    end
  end else begin : gen_no_issue_check
    assign issue_ok = 1'b1;
  end

  always_comb begin
    if (rst_ni && init_done_o) begin
      Invariants_A: assert (inv_ok);
      Model_A: assert (model_ok);
    end
    if (rst_ni && ConfBits > 0 && PipeCheck) Pipe_A: assert (pipe_ok);
    if (rst_ni && IssueReg) IssueHolds_A: assert (issue_ok);
    if (rst_ni) begin
      LookupValid_A: assert (lk_valid_o == lk_q[L]);
      if (lk_q[L]) begin
        LookupCount_A: assert (lk_count_o == exp_count_q[L]);
        LookupNodes_A: assert (nodes_ok);
      end
    end
  end
endmodule

`default_nettype wire
