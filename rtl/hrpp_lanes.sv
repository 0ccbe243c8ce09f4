`default_nettype none
// HRPP with Lanes (2 or 4) lookups and updates per cycle (docs/microarchitecture.md, "Lanes").
// Lanes = 1 is hrpp_top itself; this module is the multi-lane design, built from the same blocks.
//
//   lane l: rays in ─> [A] ─hash─> [B: key regs, key store write] ─> lookup queue ─┐
//                                                                                 crossbar
//   bank b = set index mod Lanes: hrpp_pred_table of NumSets / Lanes sets  <───────┘ (one
//           lookup and one update per bank per cycle; round-robin among the lanes)
//   lane l: <─ bank's lookup result (LookupLatency later) ─> prediction FIFO ─> predictions out
//   lane l: pw / outcome in ─> skip controller ─> update queue ─> crossbar ─> bank b's updates
//
// Each lane is hrpp_top's lane (rtl/hrpp_lane.sv, with its lookup queue): its own ray ids (a
// lane's predicted-walk results and final outcomes come back on that lane), key store, skip
// controller, prediction and skip FIFOs and update queue. The table is split by set into Lanes
// banks, each a hrpp_pred_table with its own update pipeline and same-set interlock: each set
// lives in one bank, so per set the lookups and updates stay in one sequence and the table is
// exactly the golden model's. Two lanes' requests
// for one bank in one cycle: the bank takes one (round-robin over the lanes, the pointer moves
// past the lane taken), the other waits in its lane's queue (lookups: the lookup queue, which B
// passes through when it is empty; updates: the update queue's head). All outputs come from
// registers or FIFO heads; ready outputs depend on state only.
module hrpp_lanes
  import hrpp_pkg::*;
#(
  parameter hash_variant_e Variant = DefaultVariant,
  parameter int unsigned Precision = DefaultPrecision,
  parameter int unsigned ExpBits = DefaultExpBits,
  parameter int unsigned OriginBits = DefaultOriginBits,
  parameter int unsigned DirBits = DefaultDirBits,
  parameter combine_e Combine = DefaultCombine,
  parameter dir_code_e DirCode = DefaultDirCode,  /// improved: direction grid or octahedral
  parameter int unsigned NumSets = DefaultNumSets,              /// sets, a power of two
  parameter int unsigned NumWays = DefaultNumWays,              /// ways, 2..16
  parameter int unsigned NodesPerEntry = DefaultNodesPerEntry,  /// node ids per way
  parameter int unsigned NodeIdWidth = DefaultNodeIdWidth,      /// bits of a BVH node id
  parameter int unsigned TagWidth = DefaultTagWidth,            /// stored tag bits (<= full tag)
  parameter int unsigned IdWidth = DefaultIdWidth,  /// ray id bits (per lane)
  parameter bit KeyStoreBram = DefaultKeyStoreBram,  /// each lane's key store in block RAM
  parameter bit KeyStoreReg = DefaultKeyStoreReg,  /// its read register (KeyStoreBram)
  parameter int unsigned PredFifoDepth = DefaultPredFifoDepth,  /// per lane, a power of two
  parameter int unsigned SkipFifoDepth = DefaultSkipFifoDepth,  /// per lane, a power of two
  parameter int unsigned UpdateQueueDepth = DefaultUpdateQueueDepth,  /// per lane, a power of two >= 2
  parameter bit InjectFault = DefaultInjectFault,  /// test only: a one-bit fault in the table
  parameter int unsigned Lanes = 2,  /// lanes and table banks: 2 or 4
  parameter int unsigned ConfBits = 0,  /// confidence bits: only 0 (not implemented with lanes)
  parameter bit IssueReg = DefaultIssueReg,  /// each bank's issue register (+1 cycle of update)
  localparam int unsigned IdxWidth = $clog2(NumSets),
  localparam int unsigned BankBits = $clog2(Lanes),
  localparam int unsigned BankIdxWidth = IdxWidth - BankBits,
  localparam int unsigned CountWidth = $clog2(NodesPerEntry + 1)
) (
  input  logic                                                   clk_i,
  input  logic                                                   rst_ni,
  input  mode_e                                                  cfg_mode_i,
  input  logic signed [8:0]                                      cfg_cell_exp_i,
  // Per lane: hrpp_top's interfaces
  input  logic [Lanes-1:0]                                       ray_valid_i,
  output logic [Lanes-1:0]                                       ray_ready_o,
  input  logic [Lanes-1:0][IdWidth-1:0]                          ray_id_i,
  input  logic [Lanes-1:0][2:0]                                  ray_kind_i,
  input  logic [Lanes-1:0][2:0][31:0]                            ray_org_i,
  input  logic [Lanes-1:0][2:0][31:0]                            ray_dir_i,
  output logic [Lanes-1:0]                                       pred_valid_o,
  input  logic [Lanes-1:0]                                       pred_ready_i,
  output logic [Lanes-1:0][IdWidth-1:0]                          pred_id_o,
  output logic [Lanes-1:0]                                       pred_invalid_o,
  output logic [Lanes-1:0][CountWidth-1:0]                       pred_count_o,
  output logic [Lanes-1:0][NodesPerEntry-1:0][NodeIdWidth-1:0]   pred_nodes_o,
  input  logic [Lanes-1:0]                                       pw_valid_i,
  output logic [Lanes-1:0]                                       pw_ready_o,
  input  logic [Lanes-1:0][IdWidth-1:0]                          pw_id_i,
  input  logic [Lanes-1:0]                                       pw_hit_i,
  input  logic [Lanes-1:0][NodeIdWidth-1:0]                      pw_node_i,
  input  logic [Lanes-1:0]                                       outcome_valid_i,
  output logic [Lanes-1:0]                                       outcome_ready_o,
  input  logic [Lanes-1:0][IdWidth-1:0]                          outcome_id_i,
  input  logic [Lanes-1:0]                                       outcome_hit_i,
  input  logic [Lanes-1:0][NodeIdWidth-1:0]                      outcome_node_i,
  output logic [Lanes-1:0]                                       skip_valid_o,
  input  logic [Lanes-1:0]                                       skip_ready_i,
  output logic [Lanes-1:0][IdWidth-1:0]                          skip_id_o,
  output action_e [Lanes-1:0]                                    skip_action_o
);

  typedef logic [BankBits-1:0] bank_t;

  // Lane -> bank: each lane's lookup-queue head and update-queue head; bank -> lane: grants.
  logic [Lanes-1:0]                                     lq_req;       // head needs a lookup
  bank_t [Lanes-1:0]                                    lq_bank;
  logic [Lanes-1:0][BankIdxWidth-1:0]                   lq_bidx;
  logic [Lanes-1:0][TagWidth-1:0]                       lq_tag;
  logic [Lanes-1:0]                                     lq_grant;     // its bank reads it now
  logic [Lanes-1:0]                                     uq_req;       // the queue has a head
  bank_t [Lanes-1:0]                                    uq_bank;
  logic [Lanes-1:0][BankIdxWidth-1:0]                   uq_bidx;
  logic [Lanes-1:0][TagWidth-1:0]                       uq_tag;
  logic [Lanes-1:0][NodeIdWidth-1:0]                    uq_node;
  logic [Lanes-1:0]                                     uq_demote;    // never (ConfBits 0)
  logic [Lanes-1:0]                                     uq_pop;       // its bank takes the head
  // Banks
  logic [Lanes-1:0]                                     bk_init_done;
  logic [Lanes-1:0]                                     bk_lk_valid, bk_lk_valid_o;
  logic [Lanes-1:0][BankIdxWidth-1:0]                   bk_lk_idx;
  logic [Lanes-1:0][TagWidth-1:0]                       bk_lk_tag;
  logic [Lanes-1:0][CountWidth-1:0]                     bk_lk_count;
  logic [Lanes-1:0][NodesPerEntry-1:0][NodeIdWidth-1:0] bk_lk_nodes;
  logic [Lanes-1:0]                                     bk_wr_valid, bk_wr_ready;
  logic [Lanes-1:0][BankIdxWidth-1:0]                   bk_wr_idx;
  logic [Lanes-1:0][TagWidth-1:0]                       bk_wr_tag;
  logic [Lanes-1:0][NodeIdWidth-1:0]                    bk_wr_node;
  logic [Lanes-1:0]                                     bk_wr_demote;
  logic                                                 init_done;

  assign init_done = &bk_init_done;

  // ---------------------------------------------------------------------------------------------
  // Crossbars: per bank, the first requesting lane from the round-robin pointer on; the pointer
  // moves past the lane taken (lookups: every grant; updates: a head the bank takes or drops).
  // ---------------------------------------------------------------------------------------------
  bank_t [Lanes-1:0] lk_rr_q, wr_rr_q, lk_sel, wr_sel;
  logic  [Lanes-1:0] wr_any;
  always_comb begin
    bk_lk_valid  = '0;
    bk_lk_idx    = '0;
    bk_lk_tag    = '0;
    bk_wr_valid  = '0;
    bk_wr_idx    = '0;
    bk_wr_tag    = '0;
    bk_wr_node   = '0;
    bk_wr_demote = '0;
    lk_sel       = '0;
    wr_sel       = '0;
    wr_any       = '0;
    for (int b = 0; b < Lanes; b++) begin
      for (int k = Lanes - 1; k >= 0; k--) begin
        if (lq_req[BankBits'(lk_rr_q[b] + BankBits'(k))] &&
            lq_bank[BankBits'(lk_rr_q[b] + BankBits'(k))] == BankBits'(b)) begin
          lk_sel[b]      = BankBits'(lk_rr_q[b] + BankBits'(k));
          bk_lk_valid[b] = 1'b1;
        end
        if (uq_req[BankBits'(wr_rr_q[b] + BankBits'(k))] &&
            uq_bank[BankBits'(wr_rr_q[b] + BankBits'(k))] == BankBits'(b)) begin
          wr_sel[b] = BankBits'(wr_rr_q[b] + BankBits'(k));
          wr_any[b] = 1'b1;
        end
      end
      bk_lk_idx[b]    = lq_bidx[lk_sel[b]];
      bk_lk_tag[b]    = lq_tag[lk_sel[b]];
      bk_wr_valid[b]  = wr_any[b];
      bk_wr_idx[b]    = uq_bidx[wr_sel[b]];
      bk_wr_tag[b]    = uq_tag[wr_sel[b]];
      bk_wr_node[b]   = uq_node[wr_sel[b]];
      bk_wr_demote[b] = uq_demote[wr_sel[b]];
    end
  end
  // The lanes granted (a bank's update interlock, or its full issue register I, may hold its
  // selected head: then no lane pops).
  always_comb begin
    lq_grant = '0;
    uq_pop   = '0;
    for (int b = 0; b < Lanes; b++) begin
      if (bk_lk_valid[b]) lq_grant[lk_sel[b]] = 1'b1;
      if (wr_any[b] && bk_wr_ready[b]) uq_pop[wr_sel[b]] = 1'b1;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      lk_rr_q <= '0;
      wr_rr_q <= '0;
    end else begin
      for (int b = 0; b < Lanes; b++) begin
        if (bk_lk_valid[b]) lk_rr_q[b] <= lk_sel[b] + 1'b1;
        if (wr_any[b] && bk_wr_ready[b]) wr_rr_q[b] <= wr_sel[b] + 1'b1;
      end
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Banks: the table's sets s with s mod Lanes = b, at s / Lanes.
  // ---------------------------------------------------------------------------------------------
  for (genvar b = 0; b < Lanes; b++) begin : gen_bank
    hrpp_pred_table #(
      .NumSets(NumSets / Lanes), .NumWays(NumWays), .NodesPerEntry(NodesPerEntry),
      .NodeIdWidth(NodeIdWidth), .TagWidth(TagWidth), .InjectFault(InjectFault),
      .ConfBits(ConfBits), .IssueReg(IssueReg)
    ) u_table (
      .clk_i, .rst_ni, .init_done_o(bk_init_done[b]),
      .lk_valid_i(bk_lk_valid[b]), .lk_idx_i(bk_lk_idx[b]), .lk_tag_i(bk_lk_tag[b]),
      .lk_valid_o(bk_lk_valid_o[b]), .lk_count_o(bk_lk_count[b]), .lk_nodes_o(bk_lk_nodes[b]),
      .tbl_wr_valid_i(bk_wr_valid[b]), .tbl_wr_ready_o(bk_wr_ready[b]),
      .tbl_wr_idx_i(bk_wr_idx[b]), .tbl_wr_tag_i(bk_wr_tag[b]), .tbl_wr_node_i(bk_wr_node[b]),
      .tbl_wr_demote_i(bk_wr_demote[b])
    );
  end

  // ---------------------------------------------------------------------------------------------
  // Lanes (rtl/hrpp_lane.sv, hrpp_top's lane, with a lookup queue in front of the crossbar)
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned DLast = LookupLatency - 1;

  for (genvar l = 0; l < Lanes; l++) begin : gen_lane
    logic                                      lk_valid, lk_due;
    logic [IdxWidth-1:0]                       lk_idx, wr_idx;
    logic [CountWidth-1:0]                     lk_count;
    logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes;

    hrpp_lane #(
      .Variant(Variant), .Precision(Precision), .ExpBits(ExpBits), .OriginBits(OriginBits),
      .DirBits(DirBits), .Combine(Combine), .DirCode(DirCode),
      .NumSets(NumSets), .NodesPerEntry(NodesPerEntry), .NodeIdWidth(NodeIdWidth),
      .TagWidth(TagWidth), .IdWidth(IdWidth), .KeyStoreBram(KeyStoreBram),
      .KeyStoreReg(KeyStoreReg), .PredFifoDepth(PredFifoDepth), .SkipFifoDepth(SkipFifoDepth),
      .UpdateQueueDepth(UpdateQueueDepth), .ConfBits(ConfBits), .LookupQueue(1'b1)
    ) u_lane (
      .clk_i, .rst_ni, .init_done_i(init_done), .cfg_mode_i, .cfg_cell_exp_i,
      .ray_valid_i(ray_valid_i[l]), .ray_ready_o(ray_ready_o[l]), .ray_id_i(ray_id_i[l]),
      .ray_kind_i(ray_kind_i[l]), .ray_org_i(ray_org_i[l]), .ray_dir_i(ray_dir_i[l]),
      .pred_valid_o(pred_valid_o[l]), .pred_ready_i(pred_ready_i[l]), .pred_id_o(pred_id_o[l]),
      .pred_invalid_o(pred_invalid_o[l]), .pred_count_o(pred_count_o[l]),
      .pred_nodes_o(pred_nodes_o[l]),
      .pw_valid_i(pw_valid_i[l]), .pw_ready_o(pw_ready_o[l]), .pw_id_i(pw_id_i[l]),
      .pw_hit_i(pw_hit_i[l]), .pw_node_i(pw_node_i[l]),
      .outcome_valid_i(outcome_valid_i[l]), .outcome_ready_o(outcome_ready_o[l]),
      .outcome_id_i(outcome_id_i[l]), .outcome_hit_i(outcome_hit_i[l]),
      .outcome_node_i(outcome_node_i[l]),
      .skip_valid_o(skip_valid_o[l]), .skip_ready_i(skip_ready_i[l]), .skip_id_o(skip_id_o[l]),
      .skip_action_o(skip_action_o[l]),
      .lk_valid_o(lk_valid), .lk_ready_i(lq_grant[l]), .lk_idx_o(lk_idx), .lk_tag_o(lq_tag[l]),
      .lk_due_o(lk_due), .lk_count_i(lk_count), .lk_nodes_i(lk_nodes),
      .tbl_wr_valid_o(uq_req[l]), .tbl_wr_ready_i(uq_pop[l]), .tbl_wr_idx_o(wr_idx),
      .tbl_wr_tag_o(uq_tag[l]), .tbl_wr_node_o(uq_node[l]), .tbl_wr_demote_o(uq_demote[l])
    );
    assign lq_req[l]  = lk_valid;
    assign lq_bank[l] = BankBits'(lk_idx);
    assign lq_bidx[l] = BankIdxWidth'(lk_idx >> BankBits);
    assign uq_bank[l] = BankBits'(wr_idx);
    assign uq_bidx[l] = BankIdxWidth'(wr_idx >> BankBits);

    // The bank of the lane's request travels beside its lookup (LookupLatency cycles); the lane
    // takes that bank's result when its lookup is due (a ray with an infinite or NaN component
    // has none: no prediction).
    bank_t [LookupLatency-1:0] d_bank_q;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) d_bank_q <= '0;
      else d_bank_q <= {d_bank_q[LookupLatency-2:0], lq_bank[l]};
    end
    assign lk_count = lk_due ? bk_lk_count[d_bank_q[DLast]] : '0;
    assign lk_nodes = lk_due ? bk_lk_nodes[d_bank_q[DLast]] : '0;

`ifndef SYNTHESIS
    // The bank this lane's lookup went to answers exactly when the lane expects it.
    LookupAligned_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        lk_due |-> bk_lk_valid_o[d_bank_q[DLast]]);
`endif
  end

  // ---------------------------------------------------------------------------------------------
  // Elaboration checks and assertions
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned Stages = 1 + HashLatency + 1 + LookupLatency + 1;
  if (Stages != PredictionLatency) begin : gen_latency_check
    $error("hrpp_lanes predicts in %0d cycles; hrpp_pkg::PredictionLatency declares %0d", Stages,
           PredictionLatency);
  end
  if (ConfBits != 0) begin : gen_conf_check
    $error("hrpp_lanes: ConfBits %0d: confidence bits are implemented in hrpp_top only", ConfBits);
  end
  if (Lanes != 2 && Lanes != 4) begin : gen_lanes_check
    $error("hrpp_lanes: Lanes %0d is not 2 or 4 (one lane: hrpp_top)", Lanes);
  end
  if (NumSets / Lanes < 2) begin : gen_bank_sets_check
    $error("hrpp_lanes: NumSets %0d gives banks of fewer than 2 sets", NumSets);
  end
  // Each lane counts the lookup latency of a table of NumSets sets (hrpp_lane), the banks' tables
  // have NumSets / Lanes: the two agree while no table is built of RAM banks.
  if (NumSets > TableBankDepth) begin : gen_bank_depth_check
    $error("hrpp_lanes: NumSets %0d is more than TableBankDepth (%0d): not supported", NumSets,
           TableBankDepth);
  end
  if (UpdateQueueDepth < 2 || (UpdateQueueDepth & (UpdateQueueDepth - 1)) != 0)
  begin : gen_update_queue_check
    $error("UpdateQueueDepth %0d is not a power of two >= 2", UpdateQueueDepth);
  end

`ifndef SYNTHESIS
  ReadyKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !$isunknown({ray_ready_o, pw_ready_o, outcome_ready_o, pred_valid_o, skip_valid_o}));
`endif

endmodule

`default_nettype wire
