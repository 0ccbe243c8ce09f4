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
// Each lane is hrpp_top's lane: its own ray ids (a lane's predicted-walk results and final outcomes
// come back on that lane), key store, skip controller, prediction and skip FIFOs and update
// queue. The table is split by set into Lanes banks, each a hrpp_pred_table with its own
// update pipeline and same-set interlock: each set lives in one bank, so per set the lookups and
// updates stay in one sequence and the table is exactly the golden model's. Two lanes' requests
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
  parameter int unsigned PredFifoDepth = DefaultPredFifoDepth,  /// per lane, a power of two
  parameter int unsigned SkipFifoDepth = DefaultSkipFifoDepth,  /// per lane, a power of two
  parameter int unsigned UpdateQueueDepth = DefaultUpdateQueueDepth,  /// per lane, a power of two >= 2
  parameter bit InjectFault = DefaultInjectFault,  /// test only: a one-bit fault in the table
  parameter int unsigned Lanes = 2,  /// lanes and table banks: 2 or 4
  parameter int unsigned ConfBits = 0,  /// confidence bits: only 0 (not implemented with lanes)
  localparam int unsigned IdxWidth = $clog2(NumSets),
  localparam int unsigned BankBits = $clog2(Lanes),
  localparam int unsigned BankIdxWidth = IdxWidth - BankBits,
  localparam int unsigned CountWidth = $clog2(NodesPerEntry + 1),
  localparam int unsigned KeyWidth = key_width(Variant, Precision, ExpBits, OriginBits, DirBits,
                                               Combine, DirCode)
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
  logic                                                 init_done;

  assign init_done = &bk_init_done;

  // ---------------------------------------------------------------------------------------------
  // Crossbars: per bank, the first requesting lane from the round-robin pointer on; the pointer
  // moves past the lane taken (lookups: every grant; updates: a head the bank takes or drops).
  // ---------------------------------------------------------------------------------------------
  bank_t [Lanes-1:0] lk_rr_q, wr_rr_q, lk_sel, wr_sel;
  logic  [Lanes-1:0] wr_any;
  always_comb begin
    bk_lk_valid = '0;
    bk_lk_idx   = '0;
    bk_lk_tag   = '0;
    bk_wr_valid = '0;
    bk_wr_idx   = '0;
    bk_wr_tag   = '0;
    bk_wr_node  = '0;
    lk_sel      = '0;
    wr_sel      = '0;
    wr_any      = '0;
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
      bk_lk_idx[b]   = lq_bidx[lk_sel[b]];
      bk_lk_tag[b]   = lq_tag[lk_sel[b]];
      bk_wr_valid[b] = wr_any[b];
      bk_wr_idx[b]   = uq_bidx[wr_sel[b]];
      bk_wr_tag[b]   = uq_tag[wr_sel[b]];
      bk_wr_node[b]  = uq_node[wr_sel[b]];
    end
  end
  // The lanes granted (a bank's update interlock may hold its selected head: then no lane pops).
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
      .NodeIdWidth(NodeIdWidth), .TagWidth(TagWidth), .InjectFault(InjectFault)
    ) u_table (
      .clk_i, .rst_ni, .init_done_o(bk_init_done[b]),
      .lk_valid_i(bk_lk_valid[b]), .lk_idx_i(bk_lk_idx[b]), .lk_tag_i(bk_lk_tag[b]),
      .lk_valid_o(bk_lk_valid_o[b]), .lk_count_o(bk_lk_count[b]), .lk_nodes_o(bk_lk_nodes[b]),
      .tbl_wr_valid_i(bk_wr_valid[b]), .tbl_wr_ready_o(bk_wr_ready[b]),
      .tbl_wr_idx_i(bk_wr_idx[b]), .tbl_wr_tag_i(bk_wr_tag[b]), .tbl_wr_node_i(bk_wr_node[b]),
      .tbl_wr_demote_i(1'b0)
    );
  end

  // ---------------------------------------------------------------------------------------------
  // Lanes
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned DLast = LookupLatency - 1;
  localparam int unsigned UqPtrWidth = $clog2(UpdateQueueDepth);
  localparam int unsigned UqCountWidth = $clog2(UpdateQueueDepth + 1);
  localparam int unsigned KsWidth = IdxWidth + TagWidth + 1;
  localparam int unsigned LqWidth = IdWidth + 1 + IdxWidth + TagWidth;
  localparam int unsigned PredWidth = IdWidth + 1 + CountWidth + NodesPerEntry * NodeIdWidth;
  localparam int unsigned PredCountWidth = $clog2(PredFifoDepth + 1);

  for (genvar l = 0; l < Lanes; l++) begin : gen_lane
    // A: input registers
    logic               a_valid_q;
    logic [IdWidth-1:0] a_id_q;
    logic [2:0]         a_kind_q;
    logic [2:0][31:0]   a_org_q, a_dir_q;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        a_valid_q <= 1'b0;
        a_id_q    <= '0;
        a_kind_q  <= '0;
        a_org_q   <= '0;
        a_dir_q   <= '0;
      end else begin
        a_valid_q <= ray_valid_i[l] && ray_ready_o[l];
        a_id_q    <= ray_id_i[l];
        a_kind_q  <= ray_kind_i[l];
        a_org_q   <= ray_org_i[l];
        a_dir_q   <= ray_dir_i[l];
      end
    end

    // Hash, then B: key registers
    logic [KeyWidth-1:0] key;
    logic                key_invalid;
    hrpp_hash #(
      .Variant(Variant), .Precision(Precision), .ExpBits(ExpBits), .OriginBits(OriginBits),
      .DirBits(DirBits), .Combine(Combine), .DirCode(DirCode)
    ) u_hash (
      .clk_i, .rst_ni, .org_i(a_org_q), .dir_i(a_dir_q), .cell_exp_i(cfg_cell_exp_i),
      .key_o(key), .invalid_o(key_invalid)
    );

    logic [HashLatency-1:0]              h_valid_q, h_any_hit_q;
    logic [HashLatency-1:0][IdWidth-1:0] h_id_q;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        h_valid_q   <= '0;
        h_any_hit_q <= '0;
        h_id_q      <= '0;
      end else begin
        h_valid_q   <= {h_valid_q[HashLatency-2:0], a_valid_q};
        h_any_hit_q <= {h_any_hit_q[HashLatency-2:0],
                        kind_is_any_hit(a_kind_q) || cfg_mode_i == ModeAnyHit};
        h_id_q      <= {h_id_q[HashLatency-2:0], a_id_q};
      end
    end

    logic [IdxWidth-1:0] key_idx;
    logic [TagWidth-1:0] key_tag;
    always_comb begin
      key_idx = '0;
      for (int i = 0; i < KeyWidth; i += IdxWidth) key_idx ^= IdxWidth'(key >> i);
      key_tag = TagWidth'(key >> IdxWidth);
    end

    logic                b_valid_q, b_invalid_q, b_any_hit_q;
    logic [IdWidth-1:0]  b_id_q;
    logic [IdxWidth-1:0] b_idx_q;
    logic [TagWidth-1:0] b_tag_q;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        b_valid_q   <= 1'b0;
        b_invalid_q <= 1'b0;
        b_any_hit_q <= 1'b0;
        b_id_q      <= '0;
        b_idx_q     <= '0;
        b_tag_q     <= '0;
      end else begin
        b_valid_q   <= h_valid_q[HashLatency-1];
        b_invalid_q <= key_invalid;
        b_any_hit_q <= h_any_hit_q[HashLatency-1];
        b_id_q      <= h_id_q[HashLatency-1];
        b_idx_q     <= key_idx;
        b_tag_q     <= key_tag;
      end
    end

    // Key store (as hrpp_top's, one per lane: a lane's ids are its own)
    (* ram_style = "distributed" *) logic [KsWidth-1:0] ks_mem_q[2**IdWidth];
    logic [IdxWidth-1:0] ksp_idx, ksf_idx;
    logic [TagWidth-1:0] ksp_tag, ksf_tag;
    logic                ksp_any_hit, ksf_any_hit_unused;
    logic [IdWidth-1:0]  ksp_id, ksf_id;  // the ids of the messages being accepted
    always_ff @(posedge clk_i) begin
      if (b_valid_q) ks_mem_q[b_id_q] <= {b_idx_q, b_tag_q, b_any_hit_q};
    end
    assign {ksp_idx, ksp_tag, ksp_any_hit} = ks_mem_q[ksp_id];
    assign {ksf_idx, ksf_tag, ksf_any_hit_unused} = ks_mem_q[ksf_id];

    // Lookup queue: B's ray waits here while its bank reads another lane's. Its head is the
    // oldest entry, or B itself when the queue is empty (B passes through); a ray with an
    // infinite or NaN component needs no bank and leaves at once from the head.
    logic [LqWidth-1:0]        lq_out;
    logic                      lq_empty, lq_push, lq_pop, lq_go;
    logic [PredCountWidth-1:0] lq_count;
    logic                      hd_valid, hd_invalid;
    logic [IdWidth-1:0]        hd_id;
    logic [IdxWidth-1:0]       hd_idx;
    logic [TagWidth-1:0]       hd_tag;
    assign hd_valid = !lq_empty || b_valid_q;
    assign {hd_id, hd_invalid, hd_idx, hd_tag} =
        lq_empty ? {b_id_q, b_invalid_q, b_idx_q, b_tag_q} : lq_out;
    assign lq_req[l]  = hd_valid && !hd_invalid;
    assign lq_bank[l] = BankBits'(hd_idx);
    assign lq_bidx[l] = BankIdxWidth'(hd_idx >> BankBits);
    assign lq_tag[l]  = hd_tag;
    assign lq_go      = hd_valid && (hd_invalid || lq_grant[l]);
    assign lq_push    = b_valid_q && !(lq_empty && lq_go);
    assign lq_pop     = lq_go && !lq_empty;
    hrpp_fifo #(.Depth(PredFifoDepth), .Width(LqWidth)) u_lookup_queue (
      .clk_i, .rst_ni,
      .push_i(lq_push), .data_i({b_id_q, b_invalid_q, b_idx_q, b_tag_q}),
      .pop_i(lq_pop), .data_o(lq_out), .empty_o(lq_empty), .full_o(), .count_o(lq_count)
    );

    // The ray's id, validity and bank travel beside its bank's lookup (LookupLatency cycles).
    logic [LookupLatency-1:0]              d_valid_q, d_invalid_q;
    logic [LookupLatency-1:0][IdWidth-1:0] d_id_q;
    bank_t [LookupLatency-1:0]             d_bank_q;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        d_valid_q   <= '0;
        d_invalid_q <= '0;
        d_id_q      <= '0;
        d_bank_q    <= '0;
      end else begin
        d_valid_q   <= {d_valid_q[LookupLatency-2:0], lq_go};
        d_invalid_q <= {d_invalid_q[LookupLatency-2:0], hd_invalid};
        d_id_q      <= {d_id_q[LookupLatency-2:0], hd_id};
        d_bank_q    <= {d_bank_q[LookupLatency-2:0], lq_bank[l]};
      end
    end

    // Prediction FIFO; rays are accepted while every ray in flight (A, the hash, B, the lookup
    // queue, the lookup) has a FIFO place.
    logic [PredWidth-1:0]                      pred_out;
    logic                                      pred_empty;
    logic [PredCountWidth-1:0]                 pred_count;
    logic [PredCountWidth:0]                   in_flight;
    logic [CountWidth-1:0]                     lk_count;
    logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes;
    assign lk_count = d_invalid_q[DLast] ? '0 : bk_lk_count[d_bank_q[DLast]];
    assign lk_nodes = d_invalid_q[DLast] ? '0 : bk_lk_nodes[d_bank_q[DLast]];
    hrpp_fifo #(.Depth(PredFifoDepth), .Width(PredWidth)) u_pred_fifo (
      .clk_i, .rst_ni,
      .push_i(d_valid_q[DLast]), .data_i({d_id_q[DLast], d_invalid_q[DLast], lk_count, lk_nodes}),
      .pop_i(pred_valid_o[l] && pred_ready_i[l]), .data_o(pred_out),
      .empty_o(pred_empty), .full_o(), .count_o(pred_count)
    );
    assign pred_valid_o[l] = !pred_empty;
    assign {pred_id_o[l], pred_invalid_o[l], pred_count_o[l], pred_nodes_o[l]} = pred_out;

    always_comb begin
      in_flight = (PredCountWidth + 1)'(a_valid_q) + (PredCountWidth + 1)'(b_valid_q) +
                  (PredCountWidth + 1)'(lq_count);
      for (int i = 0; i < HashLatency; i++) in_flight += (PredCountWidth + 1)'(h_valid_q[i]);
      for (int i = 0; i < LookupLatency; i++) in_flight += (PredCountWidth + 1)'(d_valid_q[i]);
    end
    assign ray_ready_o[l] = init_done && (in_flight + (PredCountWidth + 1)'(pred_count)) <
                                        (PredCountWidth + 1)'(PredFifoDepth);

    // Skip controller and update queue (as hrpp_top's)
    logic                   sc_wr_valid, sc_wr2_valid, uq_room1, uq_room2;
    logic [IdxWidth-1:0]    sc_wr_idx, sc_wr2_idx;
    logic [TagWidth-1:0]    sc_wr_tag, sc_wr2_tag;
    logic [NodeIdWidth-1:0] sc_wr_node, sc_wr2_node;
    logic                   sc_wr_demote_unused;  // never set: no confidence bits (ConfBits 0)
    hrpp_skip_ctrl #(
      .IdWidth(IdWidth), .IdxWidth(IdxWidth), .TagWidth(TagWidth), .NodeIdWidth(NodeIdWidth),
      .FifoDepth(SkipFifoDepth)
    ) u_skip (
      .clk_i, .rst_ni, .enable_i(init_done), .cfg_mode_i,
      .pw_valid_i(pw_valid_i[l]), .pw_ready_o(pw_ready_o[l]), .pw_id_i(pw_id_i[l]),
      .pw_hit_i(pw_hit_i[l]), .pw_node_i(pw_node_i[l]),
      .outcome_valid_i(outcome_valid_i[l]), .outcome_ready_o(outcome_ready_o[l]),
      .outcome_id_i(outcome_id_i[l]), .outcome_hit_i(outcome_hit_i[l]),
      .outcome_node_i(outcome_node_i[l]),
      .ksp_id_o(ksp_id), .ksp_idx_i(ksp_idx), .ksp_tag_i(ksp_tag), .ksp_any_hit_i(ksp_any_hit),
      .ksf_id_o(ksf_id), .ksf_idx_i(ksf_idx), .ksf_tag_i(ksf_tag), .ksf_pred_i(1'b0),
      .tbl_wr_valid_o(sc_wr_valid), .tbl_wr_ready_i(uq_room1), .tbl_wr_idx_o(sc_wr_idx),
      .tbl_wr_tag_o(sc_wr_tag), .tbl_wr_node_o(sc_wr_node),
      .tbl_wr_demote_o(sc_wr_demote_unused),
      .tbl_wr2_valid_o(sc_wr2_valid), .tbl_wr2_ready_i(uq_room2), .tbl_wr2_idx_o(sc_wr2_idx),
      .tbl_wr2_tag_o(sc_wr2_tag), .tbl_wr2_node_o(sc_wr2_node),
      .skip_valid_o(skip_valid_o[l]), .skip_ready_i(skip_ready_i[l]), .skip_id_o(skip_id_o[l]),
      .skip_action_o(skip_action_o[l])
    );

    typedef struct packed {
      logic [IdxWidth-1:0]    idx;
      logic [TagWidth-1:0]    tag;
      logic [NodeIdWidth-1:0] node;
    } uq_req_t;
    uq_req_t                 uq_mem_q[UpdateQueueDepth];
    uq_req_t                 uq_req1, uq_req2, uq_head_q, uq_head_d;
    logic [UqPtrWidth-1:0]   uq_rd_q, uq_wr_q;
    logic [UqCountWidth-1:0] uq_count_q;
    logic                    uq_take1, uq_take2;

    assign uq_room1 = uq_count_q <= UqCountWidth'(UpdateQueueDepth - 1);
    assign uq_room2 = uq_count_q <= UqCountWidth'(UpdateQueueDepth - 2);
    assign uq_req1  = '{idx: sc_wr_idx, tag: sc_wr_tag, node: sc_wr_node};
    assign uq_req2  = '{idx: sc_wr2_idx, tag: sc_wr2_tag, node: sc_wr2_node};
    assign uq_take1 = sc_wr_valid && uq_room1;
    assign uq_take2 = sc_wr2_valid && uq_room2;
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        uq_rd_q    <= '0;
        uq_wr_q    <= '0;
        uq_count_q <= '0;
      end else begin
        uq_rd_q    <= uq_rd_q + UqPtrWidth'(uq_pop[l]);
        uq_wr_q    <= uq_wr_q + UqPtrWidth'(uq_take1) + UqPtrWidth'(uq_take2);
        uq_count_q <= uq_count_q + UqCountWidth'(uq_take1) + UqCountWidth'(uq_take2) -
                      UqCountWidth'(uq_pop[l]);
      end
    end
    always_ff @(posedge clk_i) begin
      if (uq_take1) uq_mem_q[uq_wr_q] <= uq_req1;
      if (uq_take2) uq_mem_q[uq_wr_q + 1'b1] <= uq_req2;
    end
    function automatic uq_req_t uq_entry_after_writes(logic [UqPtrWidth-1:0] i, uq_req_t stored);
      if (uq_take1 && uq_wr_q == i) return uq_req1;
      if (uq_take2 && uq_wr_q + 1'b1 == i) return uq_req2;
      return stored;
    endfunction
    assign uq_head_d = uq_pop[l] ? uq_entry_after_writes(uq_rd_q + 1'b1, uq_mem_q[uq_rd_q + 1'b1])
                                 : uq_entry_after_writes(uq_rd_q, uq_head_q);
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) uq_head_q <= '0;
      else uq_head_q <= uq_head_d;
    end
    assign uq_req[l]  = uq_count_q != '0;
    assign uq_bank[l] = BankBits'(uq_head_q.idx);
    assign uq_bidx[l] = BankIdxWidth'(uq_head_q.idx >> BankBits);
    assign uq_tag[l]  = uq_head_q.tag;
    assign uq_node[l] = uq_head_q.node;

`ifndef SYNTHESIS
    // The bank this lane's lookup went to answers exactly when the lane expects it.
    LookupAligned_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        d_valid_q[DLast] && !d_invalid_q[DLast] |-> bk_lk_valid_o[d_bank_q[DLast]]);
    UpdateQueueBounds_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        uq_count_q <= UqCountWidth'(UpdateQueueDepth) && (!uq_pop[l] || uq_count_q != '0));
    uq_req_t uq_head_stored;
    assign uq_head_stored = uq_mem_q[uq_rd_q];
    UpdateQueueHead_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        uq_count_q != '0 |-> uq_head_q == uq_head_stored);
    PredStable_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        pred_valid_o[l] && !pred_ready_i[l] |=> pred_valid_o[l] &&
        $stable({pred_id_o[l], pred_invalid_o[l], pred_count_o[l], pred_nodes_o[l]}));
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
