`default_nettype none
// HRPP predictor table: NumSets sets x NumWays ways x NodesPerEntry node ids, true LRU over ways
// (age counters), node ids in most-recently-used-first order (docs/hash.md, "Predictor table").
//
// Two copies of the table in block RAM, written together: the lookup copy serves one lookup
// per cycle, the update copy one read-modify-write per cycle. Timing (docs/microarchitecture.md):
//   lookup: L1 read address | L2 RAM data | L3 RAM data registered, collision select, tag
//           compare | L4 way select, outputs registered: lk_valid_o four cycles after lk_valid_i;
//           a table of RAM banks (NumSets > RamBankDepth) has L3b after L3 (the bank read's row
//           registered; the collision select and tag compare there): five cycles.
//   update: [I issue register: IssueReg] | T0 read address | T1 RAM data | T2 RAM data
//           registered | C1 forward, match | C2 select the way | C3 new row | W write to both
//           copies (with RAM banks from W's copy, wb_*, whose row C3B's decisions compute beside
//           it; the update RAMs' read address from T0's copy, t0r_idx_q).
// A lookup sees every write presented in the cycle of its read or earlier. An update whose set
// equals that of an update accepted in either of the two previous cycles waits (tbl_wr_ready_o
// low; with IssueReg it waits in I, and the input waits while I is full), unless it merges into
// the newer of those two (below): then it is taken and never issued.
// Every other hazard is forwarded, so one lookup and one update per cycle are sustained.
// Without confidence bits only an identical update (set, tag and node) merges: it changes nothing
// (the update before it left its tag's way the most recently used, holding the node first).
// After reset the table clears itself, one set per cycle (NumSets cycles, init_done_o low); it
// takes no lookup and no update until init_done_o (the lane takes no ray before it).
//
// Confidence (ConfBits = 1; docs/hash.md, "Confidence", with C = 1, T = 1): each way holds a
// confidence bit beside its node list (stored in the RAM only when ConfBits = 1: the RAM word is
// the row without it otherwise). A lookup returns no prediction from a way whose bit is 0. An
// update sets the bit when its node was already in the way's list, clears it when the node is
// inserted or the way allocated. A demote request (tbl_wr_demote_i) clears the bit of the way
// holding its tag and changes nothing else (no allocation, no recency change; no way: the row is
// rewritten unchanged). A request of the set and tag of the newer same-set request in T0 / T1
// merges into it, and that request then leaves the row the two leave one after the other, in one
// pass (an update sets or clears the tag's bit whatever it was; a demote changes only that bit):
//   demote behind demote:            the demote again changes nothing;
//   demote behind update:            the update, its bit written 0 (ovr: the bit is overridden);
//   update behind demote:            the update alone (the demote's bit is overwritten);
//   update behind update, same node: the update, its bit written 1 (the node is in the list).
// An update behind an update of another node waits (the pair moves two nodes).
module hrpp_pred_table
  import hrpp_pkg::*;
#(
  parameter int unsigned NumSets = DefaultNumSets,              /// sets, a power of two
  parameter int unsigned NumWays = DefaultNumWays,              /// ways, 2..16
  parameter int unsigned NodesPerEntry = DefaultNodesPerEntry,  /// node ids per way (K), 1..8
  parameter int unsigned NodeIdWidth = DefaultNodeIdWidth,      /// bits of a node id
  parameter int unsigned TagWidth = DefaultTagWidth,            /// stored tag bits
  parameter bit InjectFault = 1'b0,  /// test only: a one-bit fault in the node update
  parameter int unsigned ConfBits = DefaultConfBits,  /// confidence bits per way: 0 or 1
  /// sets per RAM bank: a table of more sets is split into banks of this many (see Memories)
  parameter int unsigned RamBankDepth = TableBankDepth,
  /// 1: the issue register I before T0 (a request waits a cycle in it; see the interlock)
  parameter bit IssueReg = DefaultIssueReg,
  localparam int unsigned IdxWidth = $clog2(NumSets),
  localparam int unsigned CountWidth = $clog2(NodesPerEntry + 1),
  localparam int unsigned AgeWidth = $clog2(NumWays)
) (
  input  logic                                      clk_i,
  input  logic                                      rst_ni,
  output logic                                      init_done_o,  /// the reset clear is over
  // Lookup (never stalls)
  input  logic                                      lk_valid_i,
  input  logic [IdxWidth-1:0]                       lk_idx_i,
  input  logic [TagWidth-1:0]                       lk_tag_i,
  output logic                                      lk_valid_o,
  output logic [CountWidth-1:0]                     lk_count_o,  /// 0: no prediction
  output logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes_o,  /// MRU first
  // Write requests (updates): node_i becomes the most recently used node of the tag's entry
  input  logic                                      tbl_wr_valid_i,
  output logic                                      tbl_wr_ready_o,
  input  logic [IdxWidth-1:0]                       tbl_wr_idx_i,
  input  logic [TagWidth-1:0]                       tbl_wr_tag_i,
  input  logic [NodeIdWidth-1:0]                    tbl_wr_node_i,
  input  logic                                      tbl_wr_demote_i  /// a demote (ConfBits = 1)
);

  typedef struct packed {
    logic                                      valid;
    logic [TagWidth-1:0]                       tag;
    logic [CountWidth-1:0]                     count;
    logic [NodesPerEntry-1:0][NodeIdWidth-1:0] nodes;  // [0] = most recently used
    logic [AgeWidth-1:0]                       age;    // 0 = most recently used way
    logic                                      conf;   // confidence (always 0 if ConfBits = 0)
  } way_t;
  typedef way_t [NumWays-1:0] row_t;
  // The RAM word: each way's fields but its confidence bit (way w at bits [w * BaseWidth +:
  // BaseWidth], as the row without the bit), then with ConfBits = 1 the ways' confidence bits.
  localparam int unsigned BaseWidth = $bits(way_t) - 1;
  localparam int unsigned RamWidth = NumWays * (BaseWidth + ConfBits);
  function automatic logic [RamWidth-1:0] to_ram(row_t r);
    logic [RamWidth-1:0] d;
    d = '0;
    for (int w = 0; w < NumWays; w++) begin
      d[w*BaseWidth +: BaseWidth] = BaseWidth'(r[w] >> 1);
      if (ConfBits > 0) d |= RamWidth'(r[w].conf) << (NumWays * BaseWidth + w);
    end
    return d;
  endfunction
  function automatic row_t from_ram(logic [RamWidth-1:0] d);
    row_t r;
    for (int w = 0; w < NumWays; w++) begin
      r[w] = way_t'({d[w*BaseWidth +: BaseWidth], 1'b0});
      if (ConfBits > 0) r[w].conf = 1'(d >> (NumWays * BaseWidth + w));
    end
    return r;
  endfunction

  // A table write request as it travels down the update pipeline.
  typedef struct packed {
    logic                   valid;
    logic [IdxWidth-1:0]    idx;
    logic [TagWidth-1:0]    tag;
    logic [NodeIdWidth-1:0] node;
    logic                   demote;  // a demote request (ConfBits = 1), not an update
    logic                   ovr;     // ConfBits = 1: a merge fixed the bit C3 writes: ovr_bit
    logic                   ovr_bit;
  } upd_req_t;

  // The row every set holds after reset: all ways invalid, way i has age i.
  function automatic row_t init_row();
    row_t r;
    r = '0;
    for (int w = 0; w < NumWays; w++) r[w].age = AgeWidth'(w);
    return r;
  endfunction

  // ---------------------------------------------------------------------------------------------
  // Reset clear sequence and the write port
  // ---------------------------------------------------------------------------------------------
  logic                clearing_q;
  logic [IdxWidth-1:0] clear_idx_q;
  // The write port (with RAM banks each bank's is its own, from W's copy beside it: below).
  /* verilator lint_off UNUSEDSIGNAL */
  logic                we;
  logic [IdxWidth-1:0] waddr;
  row_t                wdata;
  /* verilator lint_on UNUSEDSIGNAL */
  // W: the update pipeline's last stage
  typedef struct packed {
    logic                valid;
    logic [IdxWidth-1:0] idx;
    row_t                row;
  } w_t;
  w_t w_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      clearing_q  <= 1'b1;
      clear_idx_q <= '0;
    end else if (clearing_q) begin
      clear_idx_q <= clear_idx_q + 1'b1;
      if (clear_idx_q == IdxWidth'(NumSets - 1)) clearing_q <= 1'b0;
    end
  end
  assign init_done_o = !clearing_q;

  assign we    = clearing_q || w_q.valid;
  assign waddr = clearing_q ? clear_idx_q : w_q.idx;
  assign wdata = clearing_q ? init_row() : w_q.row;

  // ---------------------------------------------------------------------------------------------
  // Memories
  // ---------------------------------------------------------------------------------------------
  // Each copy is RamBanks banks of BankDepth sets (set s in bank s / BankDepth). A block RAM
  // holds at most 2,048 words of 9 bits or more (ECP5 DP16KD), so Yosys builds a deeper RAM from
  // cascaded ones and a mux on the top address bits after their outputs, on the path out of the
  // block RAM (its clock-to-output delay is most of a cycle) to the first register. With banks,
  // every bank's data is registered straight out of its block RAM, beside the bank the read
  // addressed, and the bank select is made one stage later: L3 for a lookup, T2 -> C1 for an
  // update. With one bank (NumSets <= RamBankDepth) the bank is always 0: the plain RAM.
  localparam int unsigned RamBanks = NumSets > RamBankDepth ? NumSets / RamBankDepth : 1;
  localparam int unsigned BankDepth = NumSets / RamBanks;
  localparam int unsigned BankIdxWidth = BankDepth <= 2 ? 1 : $clog2(BankDepth);
  localparam int unsigned BankSelWidth = RamBanks <= 2 ? 1 : $clog2(RamBanks);
  function automatic logic [BankSelWidth-1:0] bank_of(logic [IdxWidth-1:0] idx);
    return RamBanks > 1 ? BankSelWidth'(idx >> $clog2(BankDepth)) : '0;
  endfunction

  logic [RamBanks-1:0][RamWidth-1:0] lk_rdata, uram_rdata;  // per bank
  logic [IdxWidth-1:0]               uram_raddr;
  logic                              uram_re;
  /* verilator lint_off UNUSEDSIGNAL */
  logic [BankIdxWidth-1:0]           lk_baddr, uram_baddr, baddr;  // addresses in a bank
  /* verilator lint_on UNUSEDSIGNAL */
  assign lk_baddr   = lk_idx_i[BankIdxWidth-1:0];
  assign uram_baddr = uram_raddr[BankIdxWidth-1:0];
  assign baddr      = waddr[BankIdxWidth-1:0];
  // The bank of the last read of each copy (the bank whose data lk_rdata / uram_rdata hold);
  // with one bank these and the bank registers after them are constant and unused.
  /* verilator lint_off UNUSEDSIGNAL */
  logic [BankSelWidth-1:0]           l2_bank_q, t1_bank_q;
  /* verilator lint_on UNUSEDSIGNAL */

  // With banks, the write ports take W's copy (wb_*, computed beside W below): its registers
  // drive the 184 RAMs and nothing else, and its row needs no clear multiplexer; with one bank,
  // unused.
  /* verilator lint_off UNUSEDSIGNAL */
  /* verilator lint_off UNDRIVEN */
  logic                wb_valid_q;
  logic [IdxWidth-1:0] wb_idx_q;
  row_t                wb_row_q;
  /* verilator lint_on UNDRIVEN */
  /* verilator lint_on UNUSEDSIGNAL */

  for (genvar b = 0; b < RamBanks; b++) begin : gen_ram_bank
    logic                    bank_we;
    logic [BankIdxWidth-1:0] bank_waddr;
    row_t                    bank_wdata;
    if (RamBanks > 1) begin : gen_wb
      // The clear writes the reset value of wb_row_q (the cleared row): no update comes while
      // the table clears (NoUpdateWhileClearing_A), so the bank's copy holds it until then.
      assign bank_we    = clearing_q ? bank_of(clear_idx_q) == BankSelWidth'(b)
                                     : wb_valid_q && bank_of(wb_idx_q) == BankSelWidth'(b);
      assign bank_waddr = clearing_q ? clear_idx_q[BankIdxWidth-1:0] : wb_idx_q[BankIdxWidth-1:0];
      assign bank_wdata = wb_row_q;
    end else begin : gen_w
      assign bank_we    = we;
      assign bank_waddr = baddr;
      assign bank_wdata = wdata;
    end
    hrpp_ram_1r1w #(.Depth(BankDepth), .Width(RamWidth)) u_lookup_ram (
      .clk_i, .re_i(lk_valid_i), .raddr_i(lk_baddr), .rdata_o(lk_rdata[b]),
      .we_i(bank_we), .waddr_i(bank_waddr), .wdata_i(to_ram(bank_wdata))
    );
    hrpp_ram_1r1w #(.Depth(BankDepth), .Width(RamWidth)) u_update_ram (
      .clk_i, .re_i(uram_re), .raddr_i(uram_baddr), .rdata_o(uram_rdata[b]),
      .we_i(bank_we), .waddr_i(bank_waddr), .wdata_i(to_ram(bank_wdata))
    );
  end

  // The bank registers load with the RAMs' read enables, as the RAMs' outputs do.
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      l2_bank_q <= '0;
      t1_bank_q <= '0;
    end else begin
      if (lk_valid_i) l2_bank_q <= bank_of(lk_idx_i);
      if (uram_re) t1_bank_q <= bank_of(uram_raddr);
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Lookup pipeline
  // ---------------------------------------------------------------------------------------------
  // Every block-RAM output goes straight into a register (its clock-to-output delay is most of
  // a cycle); the collision select, the tag compare and the way select follow in later stages.
  // L2: the RAM data; the row written in the cycle of the read, and whether it collided.
  logic                l2_valid_q, l2_collide_q;
  logic [TagWidth-1:0] l2_tag_q;
  row_t               l2_wrow_q;
  // L3: the RAM data registered (every bank's, beside the bank read), the collision flag, row.
  logic                    l3_valid_q, l3_collide_q;
  logic [TagWidth-1:0]     l3_tag_q;
  /* verilator lint_off UNUSEDSIGNAL */
  logic [BankSelWidth-1:0] l3_bank_q;  // with one bank, unused
  /* verilator lint_on UNUSEDSIGNAL */
  row_t [RamBanks-1:0]     l3_ram_q;
  row_t                    l3_wrow_q;
  // The stage in front of L4: L3 with one bank; with banks L3b (below), a cycle later.
  logic                lc_valid, lc_collide;
  logic [TagWidth-1:0] lc_tag;
  row_t                lc_ram, lc_wrow;
  // L4: per way, whether it matches, and its count and nodes.
  logic                                                   l4_valid_q;
  logic [NumWays-1:0]                                     l4_match_q;
  logic [NumWays-1:0][CountWidth-1:0]                     l4_count_q;
  logic [NumWays-1:0][NodesPerEntry-1:0][NodeIdWidth-1:0] l4_nodes_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      l2_valid_q   <= 1'b0;
      l2_collide_q <= 1'b0;
      l2_tag_q     <= '0;
      l2_wrow_q    <= '0;
      l3_valid_q   <= 1'b0;
      l3_collide_q <= 1'b0;
      l3_tag_q     <= '0;
      l3_bank_q    <= '0;
      l3_ram_q     <= '0;
      l3_wrow_q    <= '0;
    end else begin
      l2_valid_q   <= lk_valid_i;
      // No lookup comes while the table clears (NoLookupWhileClearing_A): only W's writes can
      // collide with one, so neither the compare nor the row waits for the clear's multiplexers.
      l2_collide_q <= lk_valid_i && w_q.valid && w_q.idx == lk_idx_i;
      l2_tag_q     <= lk_tag_i;
      l2_wrow_q    <= w_q.row;
      l3_valid_q   <= l2_valid_q;
      l3_collide_q <= l2_collide_q;
      l3_tag_q     <= l2_tag_q;
      l3_bank_q    <= l2_bank_q;
      for (int b = 0; b < RamBanks; b++) l3_ram_q[b] <= from_ram(lk_rdata[b]);
      l3_wrow_q    <= l2_wrow_q;
    end
  end

  // With banks, L3b: the bank read's row and L3's other registers. Every bank's data is
  // registered beside its RAM in L3 (the flow moves those registers into the RAMs); the route from
  // the 2 x 46 RAMs of a 4,096-set table to the bank select gets a cycle of its own, and the
  // collision select and tag compare work on a register beside them.
  if (RamBanks > 1) begin : gen_l3_bank_sel
    logic                l3b_valid_q, l3b_collide_q;
    logic [TagWidth-1:0] l3b_tag_q;
    row_t                l3b_ram_q, l3b_wrow_q;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        l3b_valid_q   <= 1'b0;
        l3b_collide_q <= 1'b0;
        l3b_tag_q     <= '0;
        l3b_ram_q     <= '0;
        l3b_wrow_q    <= '0;
      end else begin
        l3b_valid_q   <= l3_valid_q;
        l3b_collide_q <= l3_collide_q;
        l3b_tag_q     <= l3_tag_q;
        l3b_ram_q     <= l3_ram_q[l3_bank_q];
        l3b_wrow_q    <= l3_wrow_q;
      end
    end
    assign lc_valid   = l3b_valid_q;
    assign lc_collide = l3b_collide_q;
    assign lc_tag     = l3b_tag_q;
    assign lc_ram     = l3b_ram_q;
    assign lc_wrow    = l3b_wrow_q;
  end else begin : gen_l3_one_bank
    assign lc_valid   = l3_valid_q;
    assign lc_collide = l3_collide_q;
    assign lc_tag     = l3_tag_q;
    assign lc_ram     = l3_ram_q[0];
    assign lc_wrow    = l3_wrow_q;
  end

  // L3 (L3b): the row (the colliding write, else the RAM data of the bank read); per way, tag
  // match (with ConfBits = 1 only a way whose confidence bit is set predicts: a way below the
  // threshold counts as none).
  row_t               l3_row;
  logic [NumWays-1:0] l3_match;
  always_comb begin
    l3_row = lc_collide ? lc_wrow : lc_ram;
    for (int w = 0; w < NumWays; w++)
      l3_match[w] = l3_row[w].valid && l3_row[w].tag == lc_tag &&
                    (ConfBits == 0 || l3_row[w].conf);
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      l4_valid_q <= 1'b0;
      l4_match_q <= '0;
      l4_count_q <= '0;
      l4_nodes_q <= '0;
    end else begin
      l4_valid_q <= lc_valid;
      l4_match_q <= lc_valid ? l3_match : '0;
      for (int w = 0; w < NumWays; w++) begin
        l4_count_q[w] <= l3_row[w].count;
        l4_nodes_q[w] <= l3_row[w].nodes;
      end
    end
  end

  // L4: the matching way (at most one matches) -> registered outputs (zero without a match).
  logic [CountWidth-1:0]                         lk_count_d;
  logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes_d;
  always_comb begin
    lk_count_d = '0;
    lk_nodes_d = '0;
    for (int w = 0; w < NumWays; w++) begin
      lk_count_d |= l4_count_q[w] & {CountWidth{l4_match_q[w]}};
      lk_nodes_d |= l4_nodes_q[w] & {(NodesPerEntry * NodeIdWidth){l4_match_q[w]}};
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      lk_valid_o <= 1'b0;
      lk_count_o <= '0;
      lk_nodes_o <= '0;
    end else begin
      lk_valid_o <= l4_valid_q;
      lk_count_o <= lk_count_d;
      lk_nodes_o <= lk_nodes_d;
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Update pipeline: one packed struct of registers per stage
  // ---------------------------------------------------------------------------------------------
  // T0: the accepted request; its read address goes to the update RAM. T1: the RAM reads.
  upd_req_t t0_q, t1_q;
  // T2: the RAM data (every bank's, beside the bank read), registered: the register has no
  // other load, so it sits beside its block RAM; the long route to C1's logic (and the bank
  // select, made on the way to C1) gets a cycle of its own.
  typedef struct packed {
    upd_req_t                req;
    logic [BankSelWidth-1:0] bank;
    row_t [RamBanks-1:0]     ram;
  } t2_t;
  /* verilator lint_off UNUSEDSIGNAL */
  t2_t  t2_q;  // with one bank, t2_q.bank is unused
  /* verilator lint_on UNUSEDSIGNAL */
  row_t t2_ram;  // the RAM data of the bank read
  if (RamBanks > 1) begin : gen_t2_bank_sel
    assign t2_ram = t2_q.ram[t2_q.bank];
  end else begin : gen_t2_one_bank
    assign t2_ram = t2_q.ram[0];
  end
  // C1: the RAM data registered again, and the newest write C1's RAM read cannot see (selected
  // in T2).
  typedef struct packed {
    upd_req_t req;
    row_t     ram;
    row_t     fwd_row;
  } c1_t;
  c1_t c1_q;
  // Per way: whether C1 uses fwd_row (a bit per way, for a way's bits of C1's 2:1 mux; Yosys
  // merges the equal bits: one flip-flop each); T1 -> T2: which rows T2 forwards (set compares).
  (* keep *) logic [NumWays-1:0] c1_use_fwd_q;
  (* keep *) logic [NumWays-1:0] t2_fwd_c3_q, t2_fwd_w_q, t2_fwd_h1_q, t2_fwd_h2_q;
  // C2: the current row and, per way, one-hot decisions (see C1).
  localparam int unsigned EqGroups = (NodeIdWidth + 1) / 2;
  typedef logic [NumWays-1:0][NodesPerEntry-1:0][EqGroups-1:0] node_eq_part_t;
  typedef struct packed {
    upd_req_t           req;
    row_t               row;
    logic [NumWays-1:0] match, first_inv, oldest;
    logic               any_match, any_inv;
    node_eq_part_t      node_eq_part;
  } c2_t;
  c2_t c2_q;
  // C3: the selected way (cleared if newly allocated), which of its nodes equal the node.
  typedef struct packed {
    logic                     valid;
    logic [IdxWidth-1:0]      idx;
    logic [NodeIdWidth-1:0]   node;
    logic                     demote;
    logic                     ovr;      // a merged request fixed the bit: ovr_bit
    logic                     ovr_bit;
    row_t                     row;
    logic [NumWays-1:0]       sel;      // one-hot way to update
    way_t                     way;
    logic [NodesPerEntry-1:0] node_eq;
  } c3_t;
  c3_t  c3_q;
  row_t c3_new_row;  // C3's result
  // The rows written one (h1) and two (h2) cycles ago (for forwarding), and the set of the first.
  w_t   h1_q;
  row_t h2_row_q;

  // An update waits while the update accepted in either of the two previous cycles has its set:
  // C1 needs that update's new row, which leaves C3 only two cycles after its own C1. A request
  // that merges into the newer of those of its set (T0's if T0 has the set, else T1's) is taken
  // and not issued: same tag, and it is a demote, or that request is a demote, or both are
  // updates of one node (see the top). The merge changes that request as it moves from T0 to T1
  // or from T1 to T2 (mg_t0, mg_t1). Without confidence bits no demote occurs: an identical
  // update is dropped (it would rewrite the row unchanged; docs/microarchitecture.md).
  //
  // The request the interlock judges (iq) and its four compares against T0 and T1 (set; same key:
  // tag and demote or node). IssueReg = 0: the request at the input, compared in this cycle.
  // IssueReg = 1: the issue register I, a request taken from the input in an earlier cycle, with
  // its compares made in the cycle before, against what T0 and T1 hold now (the input's ready
  // then depends on I's registers only, not on the compares: docs/microarchitecture.md, "Issue
  // register"). A request waits a cycle in I, so the update path is a cycle longer.
  typedef struct packed {
    logic                   valid;
    logic [IdxWidth-1:0]    idx;
    logic [TagWidth-1:0]    tag;
    logic [NodeIdWidth-1:0] node;
    logic                   demote;  // ConfBits = 1 only
  } in_req_t;
  typedef struct packed {
    logic same_t0, same_t1;      // T0 (T1) is valid and of the request's set
    logic as_t0, as_t1;          // the request merges into T0's (T1's) by key
  } cmp_t;
  in_req_t wr_in, iq;
  cmp_t    iq_cmp;
  assign wr_in = '{valid: tbl_wr_valid_i, idx: tbl_wr_idx_i, tag: tbl_wr_tag_i,
                   node: tbl_wr_node_i, demote: ConfBits > 0 && tbl_wr_demote_i};
  // The key compare: request r merges into a request of tag `tag`, node `node` (`demote`) by key.
  /* verilator lint_off UNUSEDSIGNAL */  // r's valid and set
  function automatic logic same_key(in_req_t r, logic [TagWidth-1:0] tag,
                                    logic [NodeIdWidth-1:0] node, logic demote);
    return r.tag == tag && (r.demote || demote || r.node == node);
  endfunction
  /* verilator lint_on UNUSEDSIGNAL */
  logic wr_same_t0, wr_same_t1, wr_drop, wr_go;
  assign wr_same_t0 = iq_cmp.same_t0;
  assign wr_same_t1 = iq_cmp.same_t1;
  assign wr_drop    = wr_same_t0 ? iq_cmp.as_t0 : wr_same_t1 && iq_cmp.as_t1;
  // The request leaves the interlock: issued into T0, or merged (dropped).
  // No request comes while the table clears (NoUpdateWhileClearing_A), so no term waits for it.
  assign wr_go      = iq.valid && (!(wr_same_t0 || wr_same_t1) || wr_drop);
  logic wr_demote, wr_merge;
  assign wr_demote  = iq.demote;
  assign wr_merge   = ConfBits > 0 && iq.valid && wr_drop;
  // The merge changes the request in T0 (mg_t0) or T1 (mg_t1) as it moves on: an update behind a
  // demote replaces it (demote cleared, its node), and the bit C3 writes is fixed (ovr, ovr_bit):
  // a demote behind an update: 0; the same update again: 1; an update behind a demote: not fixed.
  // A demote's node is never used, so a demote takes the judged request's node whether an update
  // merges into it or not: the node path has no compare in it (only the few bits below wait for
  // wr_merge).
  logic mg_t0, mg_t1;
  assign mg_t0 = wr_merge && wr_same_t0;
  assign mg_t1 = wr_merge && !wr_same_t0;
  // {ovr, ovr_bit} of a request (a demote or not) with the request now taken merged into it
  function automatic logic [1:0] merged_ovr(logic demote);
    if (wr_demote) return demote ? 2'b00 : 2'b10;  // a demote behind a demote changes nothing
    return demote ? 2'b00 : 2'b11;
  endfunction
  // The request in T0 (T1) as it moves to T1 (T2), with the request now taken merged into it (mg).
  function automatic upd_req_t moved(upd_req_t r, logic mg);
    upd_req_t m;
    m = r;
    m.node = r.demote ? iq.node : r.node;
    m.demote = r.demote && !(mg && !wr_demote);
    if (mg) {m.ovr, m.ovr_bit} = merged_ovr(r.demote);
    return m;
  endfunction

  if (IssueReg) begin : gen_issue_reg
    in_req_t i_q;
    cmp_t    i_cmp_q, in_cmp, hold_cmp;
    logic    take;
    // I takes the input when it is empty or its request leaves in this cycle.
    assign take           = !i_q.valid || wr_go;
    assign tbl_wr_ready_o = take;
    // Next cycle's T0 is I's request if it is issued now; next cycle's T1 is T0's request as it
    // moves on (moved(): a demote takes I's node; a merge of an update turns it into an update).
    // The input's compares against both, and those of I itself if it waits (then nothing is
    // issued now: no T0 next cycle, and no merge now). Each compare is made on registers; only
    // the choice among them waits for this cycle's decision.
    logic t0_next_demote;  // T1's request next cycle is a demote
    assign t0_next_demote = t0_q.demote && !(mg_t0 && !wr_demote);
    always_comb begin
      in_cmp.same_t0 = wr_go && !wr_drop && wr_in.idx == i_q.idx;
      in_cmp.as_t0   = same_key(wr_in, i_q.tag, i_q.node, i_q.demote);
      in_cmp.same_t1 = t0_q.valid && wr_in.idx == t0_q.idx;
      in_cmp.as_t1   = wr_in.tag == t0_q.tag &&
                       (wr_in.demote || t0_next_demote ||
                        (t0_q.demote ? i_q.node == wr_in.node : t0_q.node == wr_in.node));
      hold_cmp.same_t0 = 1'b0;
      hold_cmp.as_t0   = 1'b0;
      hold_cmp.same_t1 = t0_q.valid && i_q.idx == t0_q.idx;
      hold_cmp.as_t1   = same_key(i_q, t0_q.tag, t0_q.node, t0_q.demote);
    end
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        i_q     <= '0;
        i_cmp_q <= '0;
      end else if (take) begin
        i_q     <= wr_in;
        i_cmp_q <= in_cmp;
      end else begin
        i_cmp_q <= hold_cmp;
      end
    end
    assign iq     = i_q;
    assign iq_cmp = i_cmp_q;
`ifndef SYNTHESIS
    // The compares made a cycle early are those of I's request against T0 and T1 now.
    IssueCompares_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        i_q.valid |-> i_cmp_q.same_t0 == (t0_q.valid && t0_q.idx == i_q.idx) &&
                      i_cmp_q.same_t1 == (t1_q.valid && t1_q.idx == i_q.idx) &&
                      (!i_cmp_q.same_t0 ||
                       i_cmp_q.as_t0 == same_key(i_q, t0_q.tag, t0_q.node, t0_q.demote)) &&
                      (!i_cmp_q.same_t1 ||
                       i_cmp_q.as_t1 == same_key(i_q, t1_q.tag, t1_q.node, t1_q.demote)));
`endif
  end else begin : gen_no_issue_reg
    assign iq                = wr_in;
    assign iq_cmp.same_t0    = t0_q.valid && t0_q.idx == wr_in.idx;
    assign iq_cmp.same_t1    = t1_q.valid && t1_q.idx == wr_in.idx;
    assign iq_cmp.as_t0      = same_key(wr_in, t0_q.tag, t0_q.node, t0_q.demote);
    assign iq_cmp.as_t1      = same_key(wr_in, t1_q.tag, t1_q.node, t1_q.demote);
    assign tbl_wr_ready_o    = !(wr_same_t0 || wr_same_t1) || wr_drop;
  end
  if (RamBanks > 1) begin : gen_t0_raddr
    // With banks, the update RAMs' read address is a copy of T0's set (loaded with a request, so
    // synthesis keeps it apart from t0_q), beside the RAMs it addresses (2 x 46 in `large`); T0's
    // registers stay with the interlock's compares. The RAMs read every cycle: a read without a
    // request is never used (T2 and C1 carry it with valid low).
    logic [IdxWidth-1:0] t0r_idx_q;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) t0r_idx_q <= '0;
      else if (wr_go && !wr_drop) t0r_idx_q <= iq.idx;
    end
    assign uram_re        = 1'b1;
    assign uram_raddr     = t0r_idx_q;
  end else begin : gen_t0_raddr_one_bank
    assign uram_re        = t0_q.valid;
    assign uram_raddr     = t0_q.idx;
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      t0_q         <= '0;
      t1_q         <= '0;
      t2_q         <= '0;
      c1_q         <= '0;
      c1_use_fwd_q <= '0;
      t2_fwd_c3_q  <= '0;
      t2_fwd_w_q   <= '0;
      t2_fwd_h1_q  <= '0;
      t2_fwd_h2_q  <= '0;
      h1_q         <= '0;
      h2_row_q     <= '0;
    end else begin
      t0_q.valid <= wr_go && !wr_drop;
      t0_q.idx   <= iq.idx;
      t0_q.tag   <= iq.tag;
      t0_q.node  <= iq.node;
      t0_q.demote <= wr_demote;
      t0_q.ovr   <= 1'b0;
      t0_q.ovr_bit <= 1'b0;
      t1_q       <= moved(t0_q, mg_t0);
      t2_q.req   <= moved(t1_q, mg_t1);
      t2_q.bank  <= t1_bank_q;
      for (int b = 0; b < RamBanks; b++) t2_q.ram[b] <= from_ram(uram_rdata[b]);
      c1_q.req   <= t2_q.req;
      c1_q.ram   <= t2_ram;
      // C1 needs the newest of four writes its RAM read (presented in T0, three cycles before
      // C1) cannot have seen: the row C3 computes now (written while C1 runs), the row W writes
      // now, and the rows written one (h1) and two (h2) cycles ago. The set compares are made in
      // T1 against the stages those rows are in one cycle earlier.
      t2_fwd_c3_q <= {NumWays{c2_q.req.valid && c2_q.req.idx == t1_q.idx}};
      t2_fwd_w_q  <= {NumWays{c3_q.valid && c3_q.idx == t1_q.idx}};
      t2_fwd_h1_q <= {NumWays{w_q.valid && w_q.idx == t1_q.idx}};
      t2_fwd_h2_q <= {NumWays{h1_q.valid && h1_q.idx == t1_q.idx}};
      c1_use_fwd_q <= t2_fwd_c3_q | t2_fwd_w_q | t2_fwd_h1_q | t2_fwd_h2_q;
      for (int w = 0; w < NumWays; w++)
        c1_q.fwd_row[w] <= t2_fwd_c3_q[w] ? c3_new_row[w] : t2_fwd_w_q[w] ? w_q.row[w] :
                           t2_fwd_h1_q[w] ? h1_q.row[w] : h2_row_q[w];
      h1_q     <= w_q;
      h2_row_q <= h1_q.row;
    end
  end

  // C1: the current row (newest write first); per way: tag match (at most one way matches),
  // the first invalid way and the least recently used way, all one-hot, so C2 only selects;
  // and the node compare's first level (two bits at a time), finished in C2.
  row_t               c1_row;
  logic [NumWays-1:0] c1_match, c1_invalid, c1_first_invalid, c1_oldest;
  node_eq_part_t      c1_node_eq_part;
  always_comb begin
    for (int w = 0; w < NumWays; w++) c1_row[w] = c1_use_fwd_q[w] ? c1_q.fwd_row[w] : c1_q.ram[w];
    for (int w = 0; w < NumWays; w++) begin
      c1_match[w]   = c1_row[w].valid && c1_row[w].tag == c1_q.req.tag;
      c1_invalid[w] = !c1_row[w].valid;
      c1_oldest[w]  = c1_row[w].age == AgeWidth'(NumWays - 1);
      for (int i = 0; i < NodesPerEntry; i++)
        for (int g = 0; g < EqGroups; g++)
          c1_node_eq_part[w][i][g] =
              2'(c1_row[w].nodes[i] >> (2 * g)) == 2'(c1_q.req.node >> (2 * g));
    end
    for (int w = 0; w < NumWays; w++) begin
      c1_first_invalid[w] = c1_invalid[w];
      for (int v = 0; v < w; v++)
        if (c1_invalid[v]) c1_first_invalid[w] = 1'b0;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      c2_q <= '0;
    end else begin
      c2_q.req          <= c1_q.req;
      c2_q.row          <= c1_row;
      c2_q.match        <= c1_match;
      c2_q.any_match    <= |c1_match;
      c2_q.first_inv    <= c1_first_invalid;
      c2_q.any_inv      <= |c1_invalid;
      c2_q.oldest       <= c1_oldest;
      c2_q.node_eq_part <= c1_node_eq_part;
    end
  end

  // C2: the way to update: the matching one, else the first invalid one, else the least
  // recently used one; that way (cleared when newly allocated) and its node matches.
  logic [NumWays-1:0]                    c2_sel;
  way_t                                  c2_way;
  logic [NodesPerEntry-1:0]              c2_way_node_eq;
  logic [NumWays-1:0][NodesPerEntry-1:0] c2_node_eq;  // per way: node i equals the node
  always_comb begin
    // A demote selects the matching way only (none: nothing changes; never a victim).
    c2_sel = c2_q.any_match ? c2_q.match :
             c2_q.req.demote ? '0 : c2_q.any_inv ? c2_q.first_inv : c2_q.oldest;
    for (int w = 0; w < NumWays; w++)
      for (int i = 0; i < NodesPerEntry; i++)
        c2_node_eq[w][i] = CountWidth'(i) < c2_q.row[w].count && &c2_q.node_eq_part[w][i];
    c2_way = '0;
    c2_way_node_eq = '0;
    for (int w = 0; w < NumWays; w++) begin
      c2_way         |= c2_q.row[w] & {$bits(way_t){c2_sel[w]}};
      c2_way_node_eq |= c2_node_eq[w] & {NodesPerEntry{c2_sel[w]}};
    end
    if (!c2_q.any_match) begin  // a newly allocated way (its age stays for the LRU update)
      c2_way.valid   = 1'b1;
      c2_way.tag     = c2_q.req.tag;
      c2_way.count   = '0;
      c2_way.nodes   = '0;
      c2_way.conf    = 1'b0;
      c2_way_node_eq = '0;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      c3_q <= '0;
    end else begin
      c3_q.valid   <= c2_q.req.valid;
      c3_q.idx     <= c2_q.req.idx;
      c3_q.node    <= c2_q.req.node;
      c3_q.demote  <= c2_q.req.demote;
      c3_q.ovr     <= c2_q.req.ovr;
      c3_q.ovr_bit <= c2_q.req.ovr_bit;
      c3_q.row     <= c2_q.row;
      c3_q.sel     <= c2_sel;
      c3_q.way     <= c2_way;
      c3_q.node_eq <= c2_way_node_eq;
    end
  end

  // C3: promote the node in the selected way, age every younger way by one.
  way_t                  c3_new_way;
  logic [CountWidth-1:0] c3_pos;
  always_comb begin
    // Position of the node in the list, or where it is inserted.
    c3_pos = c3_q.way.count < CountWidth'(NodesPerEntry) ? c3_q.way.count
                                                         : CountWidth'(NodesPerEntry - 1);
    for (int i = NodesPerEntry - 1; i >= 0; i--)
      if (c3_q.node_eq[i]) c3_pos = CountWidth'(i);
    c3_new_way = c3_q.way;
    if (!(|c3_q.node_eq) && c3_q.way.count < CountWidth'(NodesPerEntry))
      c3_new_way.count = c3_q.way.count + 1'b1;
    for (int i = 1; i < NodesPerEntry; i++)
      if (CountWidth'(i) <= c3_pos) c3_new_way.nodes[i] = c3_q.way.nodes[i-1];
    // InjectFault (test only): the lowest bit of a node id written to way 0 is flipped.
    c3_new_way.nodes[0] = c3_q.node ^ NodeIdWidth'(InjectFault && c3_q.sel[0]);
    c3_new_way.age = '0;
    // Confidence: set when the node was in the list (a confirmation), else cleared (inserted;
    // a new way's node_eq is 0); what a merged request left (ovr): set by the same update again,
    // cleared by a demote.
    c3_new_way.conf = ConfBits > 0 && (c3_q.ovr ? c3_q.ovr_bit : |c3_q.node_eq);
    for (int w = 0; w < NumWays; w++) begin
      c3_new_row[w] = c3_q.sel[w] ? c3_new_way : c3_q.row[w];
      if (!c3_q.sel[w] && c3_q.row[w].age < c3_q.way.age)
        c3_new_row[w].age = c3_q.row[w].age + 1'b1;
      if (c3_q.demote) begin  // the matching way's bit cleared, nothing else
        c3_new_row[w] = c3_q.row[w];
        if (c3_q.sel[w]) c3_new_row[w].conf = 1'b0;
      end
    end
  end

  // W: the new row, written to both copies.
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      w_q <= '0;
    end else begin
      w_q.valid <= c3_q.valid;
      w_q.idx   <= c3_q.idx;
      w_q.row   <= c3_new_row;
    end
  end
  // With banks, W's copy for the RAMs' write ports (above); it loads only with a write. Its row
  // is C3's result computed a second time, beside the copy (the copy sits by the RAMs, C3 by the
  // update pipeline): C2 registers, per way, what C3 decides from the selected way's compares
  // (C3B below), so each bit of the copy's row is a choice among C3's registers, one LUT deep.
  if (RamBanks > 1) begin : gen_w_ports
    // C3B, beside C3: per way, whether it takes the new way (upd), ages by one if younger than
    // the selected way (plain: neither selected nor a demote), has its bit cleared by a demote
    // (clr); for the way the update selects: whether node i moves to i + 1 (shift: i < the
    // node's position), whether the count grows (inc), its new confidence bit (conf). upd, plain
    // and clr restate C3's sel and demote, a bit each, so that a node bit's LUT has five inputs.
    typedef struct packed {
      logic [NumWays-1:0]                      upd, plain, clr, inc, conf;
      logic [NumWays-1:0][NodesPerEntry-1:0] shift;  // [i]: node i moves (bit K - 1 unused)
    } c3b_t;
    c3b_t c3b_d, c3b_q;
    always_comb begin
      for (int w = 0; w < NumWays; w++) begin
        c3b_d.upd[w]   = c2_sel[w] && !c2_q.req.demote;
        c3b_d.plain[w] = !c2_sel[w] && !c2_q.req.demote;
        c3b_d.clr[w]   = c2_sel[w] && c2_q.req.demote;
        // A new way (no match) is empty: nothing moves, its count becomes 1, its bit 0.
        c3b_d.inc[w]   = !c2_q.any_match ||
                         (!(|c2_node_eq[w]) && c2_q.row[w].count < CountWidth'(NodesPerEntry));
        c3b_d.conf[w]  = ConfBits > 0 && (c2_q.req.ovr ? c2_q.req.ovr_bit
                                                       : c2_q.any_match && |c2_node_eq[w]);
        // Node i moves when none of nodes 0..i is the node and i + 1 <= count: i < the node's
        // position (found at j: nodes 0..j - 1 move; inserted: nodes 0..min(count, K - 1) - 1).
        for (int i = 0; i < NodesPerEntry; i++) begin
          c3b_d.shift[w][i] = c2_q.any_match && CountWidth'(i + 1) <= c2_q.row[w].count;
          for (int j = 0; j <= i; j++)
            if (c2_node_eq[w][j]) c3b_d.shift[w][i] = 1'b0;
        end
      end
    end
    row_t wb_new_row;  // C3's result (c3_new_row), from C3's registers and C3B
    always_comb begin
      for (int w = 0; w < NumWays; w++) begin
        wb_new_row[w] = c3_q.row[w];
        if (c3b_q.plain[w] && c3_q.row[w].age < c3_q.way.age)
          wb_new_row[w].age = c3_q.row[w].age + 1'b1;
        if (c3b_q.clr[w]) wb_new_row[w].conf = 1'b0;
        if (c3b_q.upd[w]) begin
          wb_new_row[w].valid = c3_q.way.valid;
          wb_new_row[w].tag   = c3_q.way.tag;
          wb_new_row[w].count = c3_q.way.count + CountWidth'(c3b_q.inc[w]);
          wb_new_row[w].nodes[0] = c3_q.node ^ NodeIdWidth'(InjectFault && w == 0);
          for (int i = 1; i < NodesPerEntry; i++)
            wb_new_row[w].nodes[i] = c3b_q.shift[w][i-1] ? c3_q.way.nodes[i-1]
                                                          : c3_q.way.nodes[i];
          wb_new_row[w].age   = '0;
          wb_new_row[w].conf  = c3b_q.conf[w];
        end
      end
    end
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        c3b_q      <= '0;
        wb_valid_q <= 1'b0;
        wb_idx_q   <= '0;
        wb_row_q   <= init_row();
      end else begin
        c3b_q      <= c3b_d;
        wb_valid_q <= c3_q.valid;
        if (c3_q.valid) begin
          wb_idx_q <= c3_q.idx;
          wb_row_q <= wb_new_row;
        end
      end
    end
`ifndef SYNTHESIS
    // The copy's row is C3's.
    WbRow_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        c3_q.valid |-> wb_new_row == c3_new_row);
`endif
  end

  // ---------------------------------------------------------------------------------------------
  // Assertions
  // ---------------------------------------------------------------------------------------------
  // The pipelines have the stages hrpp_pkg declares: lookup L1 .. L4 (lk_valid_o four cycles
  // after lk_valid_i; with banks L3b too: five), update T0, T1, T2, C1, C2, C3, W.
  localparam int unsigned LookupStages = RamBanks > 1 ? 5 : 4;
  localparam int unsigned WriteStages = 7;
  if (LookupStages != lookup_latency(NumSets, RamBankDepth)) begin : gen_lookup_latency_check
    $error("the lookup takes %0d cycles; hrpp_pkg::lookup_latency declares %0d", LookupStages,
           lookup_latency(NumSets, RamBankDepth));
  end
  if (WriteStages != UpdateStages) begin : gen_update_stages_check
    $error("the update pipeline has %0d stages; hrpp_pkg::UpdateStages declares %0d",
           WriteStages, UpdateStages);
  end
  if (NumSets < 2 || (NumSets & (NumSets - 1)) != 0) begin : gen_sets_check
    $error("NumSets must be a power of two >= 2");
  end
  if (RamBankDepth < 2 || (RamBankDepth & (RamBankDepth - 1)) != 0) begin : gen_bank_check
    $error("RamBankDepth must be a power of two >= 2");
  end
  if (NumWays < 2 || NumWays > 16) begin : gen_ways_check
    $error("NumWays must be 2..16");
  end
  if (NodesPerEntry < 1 || NodesPerEntry > 8) begin : gen_nodes_check
    $error("NodesPerEntry must be 1..8");
  end
  if (TagWidth < 1 || TagWidth > 64) begin : gen_tag_check
    $error("TagWidth must be 1..64");
  end
  if (ConfBits > 1) begin : gen_conf_check
    $error("ConfBits must be 0 or 1 (a demote and a repeated demote must be idempotent)");
  end

`ifndef SYNTHESIS
  // At most one way matches a tag (an entry is only allocated when none does).
  OneWayMatches_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      c1_q.req.valid |-> $onehot0(c1_match));
  // The selected way is one-hot (a demote: at most one way, the matching one).
  SelOneHot_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      c3_q.valid |-> (c3_q.demote ? $onehot0(c3_q.sel) : $onehot(c3_q.sel)));
  // Without confidence bits no demote enters the pipeline, no merge fixes a bit and no bit is
  // ever set.
  if (ConfBits == 0) begin : gen_no_conf_check
    logic w_any_conf;
    always_comb begin
      w_any_conf = 1'b0;
      for (int w = 0; w < NumWays; w++) w_any_conf |= w_q.row[w].conf;
    end
    NoConfidence_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        !t0_q.demote && !c3_q.ovr && !w_any_conf);
  end
  // A merge fixes the bit of an update only (ConfBits = 0: never; see below).
  OverrideOnUpdate_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      c3_q.ovr |-> c3_q.valid && !c3_q.demote);
  // Updates of one set are at least three cycles apart (the interlock).
  SameSetSpacing_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      c1_q.req.valid |-> !(c2_q.req.valid && c2_q.req.idx == c1_q.req.idx) &&
                         !(c3_q.valid && c3_q.idx == c1_q.req.idx));
  // At most one way matches in a lookup too.
  LookupOneMatch_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      $onehot0(l4_match_q));
  // No lookup while the table clears (the lanes take no ray before init_done_o): L2's collision
  // compare looks at W's writes only.
  NoLookupWhileClearing_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      clearing_q |-> !lk_valid_i);
  // No update request while the table clears (the skip controller is enabled by init_done_o):
  // the clear has the write port, and tbl_wr_ready_o does not wait for it.
  NoUpdateWhileClearing_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      clearing_q |-> !tbl_wr_valid_i);
  // Lookup outputs are never X.
  LookupKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      lk_valid_o |-> !$isunknown({lk_count_o, lk_nodes_o}));
`endif

endmodule

`default_nettype wire
