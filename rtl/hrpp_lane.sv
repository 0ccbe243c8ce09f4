`default_nettype none
// HRPP lane: everything between a traversal engine's ray stream and the predictor table except the
// table itself (docs/microarchitecture.md has the interfaces, the pipeline and a timing diagram).
// hrpp_top is one lane connected straight to one hrpp_pred_table; hrpp_lanes is Lanes lanes, each
// with its own ray ids, around a table split by set into banks (crossbars between).
//
//   rays in ──> [A: input regs] ─hash (3 stages)─> [B: key regs, key store write] ─> lookup
//               request (─> lookup queue, LookupQueue = 1) ... lookup result (LookupCycles
//               cycles after the request is taken) ─> prediction FIFO ──> predictions out
//   predicted-walk results, final outcomes in ──> skip controller ──> update queue ──> table
//                                                                 └──> skip decisions out
//
// All outputs come from registers or FIFO heads; ready outputs depend on state only (lk_ready_i
// and tbl_wr_ready_i, the table's answers to this lane's requests, may depend on those requests).
module hrpp_lane
  import hrpp_pkg::*;
#(
  // Hash (docs/hash.md)
  parameter hash_variant_e Variant = DefaultVariant,
  parameter int unsigned Precision = DefaultPrecision,
  parameter int unsigned ExpBits = DefaultExpBits,
  parameter int unsigned OriginBits = DefaultOriginBits,
  parameter int unsigned DirBits = DefaultDirBits,
  parameter combine_e Combine = DefaultCombine,
  parameter dir_code_e DirCode = DefaultDirCode,  /// improved: direction grid or octahedral
  // The table's geometry (the whole table's, over all banks)
  parameter int unsigned NumSets = DefaultNumSets,              /// sets, a power of two
  parameter int unsigned NodesPerEntry = DefaultNodesPerEntry,  /// node ids per way
  parameter int unsigned NodeIdWidth = DefaultNodeIdWidth,      /// bits of a BVH node id
  parameter int unsigned TagWidth = DefaultTagWidth,            /// stored tag bits (<= full tag)
  // Interfaces
  parameter int unsigned IdWidth = DefaultIdWidth,  /// ray id bits: rays in flight are distinct
  parameter bit KeyStoreBram = DefaultKeyStoreBram,  /// key store in block RAM (+1 cycle)
  parameter bit KeyStoreReg = DefaultKeyStoreReg,  /// its read register (KeyStoreBram; +1 cycle)
  parameter int unsigned PredFifoDepth = DefaultPredFifoDepth,  /// a power of two
  parameter int unsigned SkipFifoDepth = DefaultSkipFifoDepth,  /// a power of two
  parameter int unsigned UpdateQueueDepth = DefaultUpdateQueueDepth,  /// update queue entries, a power of two >= 2
  parameter int unsigned ConfBits = DefaultConfBits,  /// confidence bit per table way: 0 or 1
  /// 0: the table takes every lookup request at once (hrpp_top; lk_ready_i must be 1 then);
  /// 1: a request may wait (lk_ready_i low) in a lookup queue of PredFifoDepth entries
  parameter bit LookupQueue = 1'b0,
  localparam int unsigned IdxWidth = $clog2(NumSets),
  localparam int unsigned CountWidth = $clog2(NodesPerEntry + 1),
  /// the table's lookup latency (one cycle more for a table of RAM banks: hrpp_pkg)
  localparam int unsigned LookupCycles = lookup_latency(NumSets, TableBankDepth),
  localparam int unsigned KeyWidth = key_width(Variant, Precision, ExpBits, OriginBits, DirBits,
                                               Combine, DirCode)
) (
  input  logic                                       clk_i,
  input  logic                                       rst_ni,
  input  logic                                       init_done_i,  /// the table's reset clear done
  // Configuration (hold stable while rays are in flight)
  input  mode_e                                      cfg_mode_i,
  input  logic signed [8:0]                          cfg_cell_exp_i,  /// improved hash cell size
  // Rays, predictions, predicted-walk results, final outcomes, skip decisions: hrpp_top's ports
  input  logic                                       ray_valid_i,
  output logic                                       ray_ready_o,
  input  logic [IdWidth-1:0]                         ray_id_i,
  input  logic [2:0]                                 ray_kind_i,
  input  logic [2:0][31:0]                           ray_org_i,
  input  logic [2:0][31:0]                           ray_dir_i,
  output logic                                       pred_valid_o,
  input  logic                                       pred_ready_i,
  output logic [IdWidth-1:0]                         pred_id_o,
  output logic                                       pred_invalid_o,  /// infinite/NaN ray
  output logic [CountWidth-1:0]                      pred_count_o,    /// 0: no prediction
  output logic [NodesPerEntry-1:0][NodeIdWidth-1:0]  pred_nodes_o,    /// MRU first
  input  logic                                       pw_valid_i,
  output logic                                       pw_ready_o,
  input  logic [IdWidth-1:0]                         pw_id_i,
  input  logic                                       pw_hit_i,     /// a predicted subtree hit
  input  logic [NodeIdWidth-1:0]                     pw_node_i,    /// ... this one
  input  logic                                       outcome_valid_i,
  output logic                                       outcome_ready_o,
  input  logic [IdWidth-1:0]                         outcome_id_i,
  input  logic                                       outcome_hit_i,   /// write outcome_node_i
  input  logic [NodeIdWidth-1:0]                     outcome_node_i,  /// node to insert/refresh
  output logic                                       skip_valid_o,
  input  logic                                       skip_ready_i,
  output logic [IdWidth-1:0]                         skip_id_o,
  output action_e                                    skip_action_o,
  // Lookup requests (B, or the lookup queue's head); taken when lk_ready_i
  output logic                                       lk_valid_o,
  input  logic                                       lk_ready_i,
  output logic [IdxWidth-1:0]                        lk_idx_o,
  output logic [TagWidth-1:0]                        lk_tag_o,
  // The lookup taken LookupCycles cycles ago: lk_due_o says one is due now, its result in
  output logic                                       lk_due_o,
  input  logic [CountWidth-1:0]                      lk_count_i,
  input  logic [NodesPerEntry-1:0][NodeIdWidth-1:0]  lk_nodes_i,
  // Table write requests: the update queue's head; popped when tbl_wr_ready_i
  output logic                                       tbl_wr_valid_o,
  input  logic                                       tbl_wr_ready_i,
  output logic [IdxWidth-1:0]                        tbl_wr_idx_o,
  output logic [TagWidth-1:0]                        tbl_wr_tag_o,
  output logic [NodeIdWidth-1:0]                     tbl_wr_node_o,
  output logic                                       tbl_wr_demote_o  /// a demote (ConfBits = 1)
);

  logic init_done;
  assign init_done = init_done_i;

  // ---------------------------------------------------------------------------------------------
  // A: input registers
  // ---------------------------------------------------------------------------------------------
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
      a_valid_q <= ray_valid_i && ray_ready_o;
      a_id_q    <= ray_id_i;
      a_kind_q  <= ray_kind_i;
      a_org_q   <= ray_org_i;
      a_dir_q   <= ray_dir_i;
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Hash (HashLatency stages; the id and query type travel beside it), then B: key registers
  // ---------------------------------------------------------------------------------------------
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

  // Set index: XOR of all IdxWidth-bit chunks of the key; tag: the key above the index.
  logic [IdxWidth-1:0] key_idx;
  logic [TagWidth-1:0] key_tag;
  always_comb begin
    key_idx = '0;
    for (int c = 0; c < KeyWidth; c += IdxWidth) key_idx ^= IdxWidth'(key >> c);
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

  // Key store: each in-flight ray's set, tag and query type, by id, written in B. KeyStoreBram
  // = 0: distributed RAM, read combinationally as a predicted-walk result or final outcome is
  // accepted, into the skip controller's P0 / F0 registers. KeyStoreBram = 1 (many ray ids): two
  // block-RAM copies (one per read port), read as the message is accepted into a register stage
  // in front of the skip controller (K: the message, and the RAM's output register); the RAM's
  // data goes straight into P0 / F0 one cycle later. The block RAM's slow clock-to-output thus
  // starts no logic (the handshake paths start at P0 / F0 as before), at one cycle more of
  // decision and update latency (docs/microarchitecture.md, "Key store"). KeyStoreReg = 1: the
  // RAM's data goes into a register first (J: the message and the key, the key register being
  // the block RAM's own output register in the ECP5 flow), and from J into P0 / F0: the RAM's
  // clock-to-output then ends at the RAM, at one more cycle of decision and update latency.
  localparam int unsigned KsWidth = IdxWidth + TagWidth + 1;
  logic [IdWidth-1:0]  ksp_id, ksf_id;  // the skip controller's read addresses (distributed RAM)
  logic [IdxWidth-1:0] ksp_idx, ksf_idx;
  logic [TagWidth-1:0] ksp_tag, ksf_tag;
  logic                ksp_any_hit, ksf_any_hit_unused;
  logic [KsWidth-1:0]  ks_wdata;
  assign ks_wdata = {b_idx_q, b_tag_q, b_any_hit_q};
  // The skip controller's message inputs: the ports (distributed RAM) or K (block RAM).
  logic                   sc_pw_valid, sc_pw_ready, sc_pw_hit;
  logic                   sc_outcome_valid, sc_outcome_ready, sc_outcome_hit;
  logic [IdWidth-1:0]     sc_pw_id, sc_outcome_id;
  logic [NodeIdWidth-1:0] sc_pw_node, sc_outcome_node;
  // KeyStoreBram: [0] K takes the outcome at the port, [1] J takes K's (KeyStoreReg). One net:
  // a configuration without the block-RAM key store has the nets it had before J, and Yosys
  // maps it to the same netlist (a new net alone changed ABC's mapping of `primary`).
  logic [1:0]             ks_outcome_load;
  logic [1:0]             ks_load_unused;   // read by the pred-given bit's registers only
  assign ks_load_unused = ks_outcome_load;

  if (!KeyStoreBram) begin : gen_ks_distributed
    (* ram_style = "distributed" *) logic [KsWidth-1:0] ks_mem_q[2**IdWidth];
    always_ff @(posedge clk_i) begin
      if (b_valid_q) ks_mem_q[b_id_q] <= ks_wdata;
    end
    assign {ksp_idx, ksp_tag, ksp_any_hit} = ks_mem_q[ksp_id];
    assign {ksf_idx, ksf_tag, ksf_any_hit_unused} = ks_mem_q[ksf_id];
    assign {sc_pw_valid, sc_pw_id, sc_pw_hit, sc_pw_node} = {pw_valid_i, pw_id_i, pw_hit_i,
                                                             pw_node_i};
    assign {sc_outcome_valid, sc_outcome_id, sc_outcome_hit, sc_outcome_node} =
        {outcome_valid_i, outcome_id_i, outcome_hit_i, outcome_node_i};
    assign pw_ready_o      = sc_pw_ready;
    assign outcome_ready_o = sc_outcome_ready;
    assign ks_outcome_load = '0;  // unused
  end else begin : gen_ks_bram
    // K: a message waits here while its ray's key is read; it moves on to P0 / F0 (J with
    // KeyStoreReg) when that takes it, and K takes the next (the RAM reads only then: its output
    // holds).
    logic                   kp_valid_q, kp_hit_q, kf_valid_q, kf_hit_q, kp_load, kf_load;
    logic                   kp_next, kf_next;  // the stage after K takes its message
    logic [IdWidth-1:0]     kp_id_q, kf_id_q;
    logic [NodeIdWidth-1:0] kp_node_q, kf_node_q;
    logic [KsWidth-1:0]     ksp_rd, ksf_rd;  // the RAMs' data: K's rays' keys
    logic [IdWidth-1:0]     ks_unused;  // the skip controller's read addresses
    assign ks_unused = ksp_id ^ ksf_id;
    assign kp_load = init_done && (!kp_valid_q || kp_next);
    assign kf_load = init_done && (!kf_valid_q || kf_next);
    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        kp_valid_q <= 1'b0;
        kp_id_q    <= '0;
        kp_hit_q   <= 1'b0;
        kp_node_q  <= '0;
        kf_valid_q <= 1'b0;
        kf_id_q    <= '0;
        kf_hit_q   <= 1'b0;
        kf_node_q  <= '0;
      end else begin
        if (kp_load) begin
          kp_valid_q <= pw_valid_i;
          kp_id_q    <= pw_id_i;
          kp_hit_q   <= pw_hit_i;
          kp_node_q  <= pw_node_i;
        end
        if (kf_load) begin
          kf_valid_q <= outcome_valid_i;
          kf_id_q    <= outcome_id_i;
          kf_hit_q   <= outcome_hit_i;
          kf_node_q  <= outcome_node_i;
        end
      end
    end
    // An entry is never read in the cycle it is written: a ray's result arrives after its
    // prediction left, and an id is reused only after its ray finished.
    hrpp_ram_1r1w #(.Depth(2**IdWidth), .Width(KsWidth)) u_ks_pw (
      .clk_i, .re_i(kp_load), .raddr_i(pw_id_i), .rdata_o(ksp_rd),
      .we_i(b_valid_q), .waddr_i(b_id_q), .wdata_i(ks_wdata)
    );
    hrpp_ram_1r1w #(.Depth(2**IdWidth), .Width(KsWidth)) u_ks_outcome (
      .clk_i, .re_i(kf_load), .raddr_i(outcome_id_i),
      .rdata_o(ksf_rd),
      .we_i(b_valid_q), .waddr_i(b_id_q), .wdata_i(ks_wdata)
    );
    if (!KeyStoreReg) begin : gen_ks_noreg
      assign {sc_pw_valid, sc_pw_id, sc_pw_hit, sc_pw_node} = {kp_valid_q, kp_id_q, kp_hit_q,
                                                               kp_node_q};
      assign {sc_outcome_valid, sc_outcome_id, sc_outcome_hit, sc_outcome_node} =
          {kf_valid_q, kf_id_q, kf_hit_q, kf_node_q};
      assign {ksp_idx, ksp_tag, ksp_any_hit} = ksp_rd;
      assign {ksf_idx, ksf_tag, ksf_any_hit_unused} = ksf_rd;
      assign kp_next = sc_pw_ready;
      assign kf_next = sc_outcome_ready;
      assign ks_outcome_load[1] = 1'b0;  // unused
    end else begin : gen_ks_reg
      // J: K's message and its ray's key from the RAM, taken when J is empty or moves on to P0 /
      // F0. The key registers have no reset and load only with J (the ECP5 flow makes them the
      // RAM's output register, the load its OCE: rtl/syn/outreg.py).
      logic                   jp_valid_q, jp_hit_q, jf_valid_q, jf_hit_q, jp_load, jf_load;
      logic [IdWidth-1:0]     jp_id_q, jf_id_q;
      logic [NodeIdWidth-1:0] jp_node_q, jf_node_q;
      logic [KsWidth-1:0]     jp_key_q, jf_key_q;
      assign jp_load = init_done && (!jp_valid_q || sc_pw_ready);
      assign jf_load = init_done && (!jf_valid_q || sc_outcome_ready);
      always_ff @(posedge clk_i or negedge rst_ni) begin
        if (!rst_ni) begin
          jp_valid_q <= 1'b0;
          jp_id_q    <= '0;
          jp_hit_q   <= 1'b0;
          jp_node_q  <= '0;
          jf_valid_q <= 1'b0;
          jf_id_q    <= '0;
          jf_hit_q   <= 1'b0;
          jf_node_q  <= '0;
        end else begin
          if (jp_load) begin
            jp_valid_q <= kp_valid_q;
            jp_id_q    <= kp_id_q;
            jp_hit_q   <= kp_hit_q;
            jp_node_q  <= kp_node_q;
          end
          if (jf_load) begin
            jf_valid_q <= kf_valid_q;
            jf_id_q    <= kf_id_q;
            jf_hit_q   <= kf_hit_q;
            jf_node_q  <= kf_node_q;
          end
        end
      end
      always_ff @(posedge clk_i) begin
        if (jp_load) jp_key_q <= ksp_rd;
        if (jf_load) jf_key_q <= ksf_rd;
      end
      assign {sc_pw_valid, sc_pw_id, sc_pw_hit, sc_pw_node} = {jp_valid_q, jp_id_q, jp_hit_q,
                                                               jp_node_q};
      assign {sc_outcome_valid, sc_outcome_id, sc_outcome_hit, sc_outcome_node} =
          {jf_valid_q, jf_id_q, jf_hit_q, jf_node_q};
      assign {ksp_idx, ksp_tag, ksp_any_hit} = jp_key_q;
      assign {ksf_idx, ksf_tag, ksf_any_hit_unused} = jf_key_q;
      assign kp_next = jp_load;
      assign kf_next = jf_load;
      assign ks_outcome_load[1] = jf_load;
    end
    assign pw_ready_o      = kp_load;
    assign outcome_ready_o = kf_load;
    assign ks_outcome_load[0] = kf_load;
  end

  // ---------------------------------------------------------------------------------------------
  // Lookup requests. LookupQueue = 0: B's, taken at once. LookupQueue = 1: B's ray waits in the
  // lookup queue while its bank reads another lane's; the request is the queue's oldest entry,
  // or B itself when the queue is empty (B passes through); a ray with an infinite or NaN
  // component needs no lookup and leaves at once from the head.
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned PredCountWidth = $clog2(PredFifoDepth + 1);
  logic                      hd_go, hd_invalid;  // the head leaves for the lookup stages
  logic [IdWidth-1:0]        hd_id;
  logic [PredCountWidth-1:0] lq_count;           // rays in the lookup queue

  if (!LookupQueue) begin : gen_no_lookup_queue
    assign lk_valid_o = b_valid_q && !b_invalid_q;
    assign lk_idx_o   = b_idx_q;
    assign lk_tag_o   = b_tag_q;
    assign hd_go      = b_valid_q;
    assign hd_invalid = b_invalid_q;
    assign hd_id      = b_id_q;
    assign lq_count   = '0;
`ifndef SYNTHESIS
    // The table takes every request at once.
    LookupTaken_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        lk_valid_o |-> lk_ready_i);
`endif
  end else begin : gen_lookup_queue
    localparam int unsigned LqWidth = IdWidth + 1 + IdxWidth + TagWidth;
    logic [LqWidth-1:0]  lq_out;
    logic                lq_empty, lq_push, lq_pop, hd_valid;
    logic [IdxWidth-1:0] hd_idx;
    logic [TagWidth-1:0] hd_tag;
    assign hd_valid = !lq_empty || b_valid_q;
    assign {hd_id, hd_invalid, hd_idx, hd_tag} =
        lq_empty ? {b_id_q, b_invalid_q, b_idx_q, b_tag_q} : lq_out;
    assign lk_valid_o = hd_valid && !hd_invalid;
    assign lk_idx_o   = hd_idx;
    assign lk_tag_o   = hd_tag;
    assign hd_go      = hd_valid && (hd_invalid || lk_ready_i);
    assign lq_push    = b_valid_q && !(lq_empty && hd_go);
    assign lq_pop     = hd_go && !lq_empty;
    hrpp_fifo #(.Depth(PredFifoDepth), .Width(LqWidth)) u_lookup_queue (
      .clk_i, .rst_ni,
      .push_i(lq_push), .data_i({b_id_q, b_invalid_q, b_idx_q, b_tag_q}),
      .pop_i(lq_pop), .data_o(lq_out), .empty_o(lq_empty), .full_o(), .count_o(lq_count)
    );
  end

  // ---------------------------------------------------------------------------------------------
  // Skip controller's table write requests, queued (U) before the table (tbl_wr_*)
  // ---------------------------------------------------------------------------------------------
  logic                                      tbl_wr_valid, tbl_wr_ready, tbl_wr_demote;
  logic                                      sc_tbl_wr_demote;
  logic [IdxWidth-1:0]                       tbl_wr_idx;
  logic [TagWidth-1:0]                       tbl_wr_tag;
  logic [NodeIdWidth-1:0]                    tbl_wr_node;
  logic                                      sc_tbl_wr_valid, sc_tbl_wr2_valid;
  logic [IdxWidth-1:0]                       sc_tbl_wr_idx, sc_tbl_wr2_idx;
  logic [TagWidth-1:0]                       sc_tbl_wr_tag, sc_tbl_wr2_tag;
  logic [NodeIdWidth-1:0]                    sc_tbl_wr_node, sc_tbl_wr2_node;
  logic                                      uq_room1, uq_room2;

  assign tbl_wr_ready = tbl_wr_ready_i;
  assign {tbl_wr_valid_o, tbl_wr_idx_o, tbl_wr_tag_o, tbl_wr_node_o, tbl_wr_demote_o} =
      {tbl_wr_valid, tbl_wr_idx, tbl_wr_tag, tbl_wr_node, tbl_wr_demote};

  // Update queue (UpdateQueueDepth entries, registers): takes up to two requests per cycle (a
  // final outcome's and a predicted-walk result's, in that order) and gives the table one. The
  // skip controller sees only whether it has room for one and for two (from the count register),
  // so its handshake does not wait for the table's same-set interlock, which looks at the
  // queue's head, or with the table's issue register (IssueReg) at the request it took from it
  // (and drops a request identical to the newer same-set update in T0/T1).
  localparam int unsigned UqPtrWidth = $clog2(UpdateQueueDepth);
  localparam int unsigned UqCountWidth = $clog2(UpdateQueueDepth + 1);
  typedef struct packed {
    logic [IdxWidth-1:0]    idx;
    logic [TagWidth-1:0]    tag;
    logic [NodeIdWidth-1:0] node;
    logic                   demote;  // a demote (ConfBits = 1), not an update
  } uq_req_t;
  uq_req_t                 uq_mem_q[UpdateQueueDepth];
  uq_req_t                 uq_req1, uq_req2, uq_head_q, uq_head_d;
  // The binary pointers and count (uq_rd_q, uq_wr_q, uq_count_q) are the reference the
  // assertions below check the registers the logic uses against (synthesis removes them).
  logic [UqPtrWidth-1:0]   uq_rd_q, uq_wr_q;
  logic [UqPtrWidth-1:0]   uq_rd1_q;  // uq_rd_q + 1, a register
  // One-hot write pointers: uq_wr_oh_q[i] = (uq_wr_q == i), uq_wr1_oh_q[i] = (uq_wr_q + 1 == i)
  logic [UpdateQueueDepth-1:0] uq_wr_oh_q, uq_wr1_oh_q;
  logic [UqCountWidth-1:0] uq_count_q;
  logic [UpdateQueueDepth:0] uq_cnt_oh_q;  // one-hot: uq_cnt_oh_q[k] = (uq_count_q == k)
  logic                    uq_take1, uq_take2, uq_pop;

  // The flags the handshake and the head need come from the one-hot count, a flip-flop each.
  assign uq_room1 = !uq_cnt_oh_q[UpdateQueueDepth];
  assign uq_room2 = !uq_cnt_oh_q[UpdateQueueDepth] && !uq_cnt_oh_q[UpdateQueueDepth-1];
  assign uq_req1  = '{idx: sc_tbl_wr_idx, tag: sc_tbl_wr_tag, node: sc_tbl_wr_node,
                      demote: ConfBits > 0 && sc_tbl_wr_demote};
  assign uq_req2  = '{idx: sc_tbl_wr2_idx, tag: sc_tbl_wr2_tag, node: sc_tbl_wr2_node,
                      demote: 1'b0};  // a predicted-walk result's refresh: always an update
  // Taken: the skip controller's messages advance.
  assign uq_take1 = sc_tbl_wr_valid && uq_room1;
  assign uq_take2 = sc_tbl_wr2_valid && uq_room2;  // the first is taken too
  assign uq_pop   = tbl_wr_valid && tbl_wr_ready;

  function automatic logic [UpdateQueueDepth-1:0] uq_rotl(logic [UpdateQueueDepth-1:0] x,
                                                           int unsigned n);  // n <= 2
    return UpdateQueueDepth'((x << n) | (x >> (UpdateQueueDepth - n)));
  endfunction

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      uq_rd_q     <= '0;
      uq_wr_q     <= '0;
      uq_rd1_q    <= UqPtrWidth'(1);
      uq_wr_oh_q  <= UpdateQueueDepth'(1);
      uq_wr1_oh_q <= UpdateQueueDepth'(2);
      uq_count_q  <= '0;
      uq_cnt_oh_q <= (UpdateQueueDepth + 1)'(1);
    end else begin
      uq_rd_q    <= uq_rd_q + UqPtrWidth'(uq_pop);
      uq_rd1_q   <= uq_rd1_q + UqPtrWidth'(uq_pop);
      uq_wr_q    <= uq_wr_q + UqPtrWidth'(uq_take1) + UqPtrWidth'(uq_take2);
      uq_wr_oh_q  <= uq_rotl(uq_wr_oh_q, 32'(uq_take1) + 32'(uq_take2));
      uq_wr1_oh_q <= uq_rotl(uq_wr1_oh_q, 32'(uq_take1) + 32'(uq_take2));
      uq_count_q <= uq_count_q + UqCountWidth'(uq_take1) + UqCountWidth'(uq_take2) -
                    UqCountWidth'(uq_pop);
      // take2 implies take1: the count moves by -1, 0, +1 or +2.
      unique case ({uq_take1, uq_take2, uq_pop})
        3'b001:         uq_cnt_oh_q <= uq_cnt_oh_q >> 1;
        3'b100, 3'b111: uq_cnt_oh_q <= uq_cnt_oh_q << 1;
        3'b110:         uq_cnt_oh_q <= uq_cnt_oh_q << 2;
        default:        uq_cnt_oh_q <= uq_cnt_oh_q;  // 000, 101
      endcase
    end
  end
  always_ff @(posedge clk_i) begin
    for (int unsigned i = 0; i < UpdateQueueDepth; i++) begin
      if (uq_take1 && uq_wr_oh_q[i]) uq_mem_q[i] <= uq_req1;
      if (uq_take2 && uq_wr1_oh_q[i]) uq_mem_q[i] <= uq_req2;  // behind the first, taken too
    end
  end
  // The head, registered (a copy of uq_mem_q[uq_rd_q]): the table's interlock compares it with
  // T0 and T1 and pops it in the same cycle (with IssueReg the table takes it into I when I is
  // free, and compares it there), so no read multiplexer sits in front of that. Its next value:
  // the entry at the next read pointer after this cycle's writes, needed only when the queue is
  // not empty after this cycle. Which write lands there follows from the count (the write
  // pointer is the read pointer plus the count): when the head stays, the first request does
  // when the queue is empty (the second cannot: it needs room for two); when the head leaves,
  // the first request does when one entry is in, else the entry behind the head (no write lands
  // there: the second request behind the first needs the queue empty, and a pop needs it not).
  // In both cases a queue left empty has no head, so the first request's candidate is taken
  // whether or not it is taken into the queue: the head does not wait for the skip controller's
  // handshake (uq_take1, uq_take2). UpdateQueueHeadNext_A below checks this against the
  // pointers. The pop (the table's interlock, late in the cycle) only selects between the two
  // candidates (kept as nets so that synthesis does not fold the select into the candidates'
  // logic: docs/microarchitecture.md, "Clock speed").
  (* keep *) uq_req_t uq_head_if_pop, uq_head_if_hold;
  assign uq_head_if_pop  = uq_cnt_oh_q[1] ? uq_req1 : uq_mem_q[uq_rd1_q];
  assign uq_head_if_hold = uq_cnt_oh_q[0] ? uq_req1 : uq_head_q;
  assign uq_head_d = uq_pop ? uq_head_if_pop : uq_head_if_hold;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) uq_head_q <= '0;
    else uq_head_q <= uq_head_d;
  end
  assign tbl_wr_valid = !uq_cnt_oh_q[0];
  assign {tbl_wr_idx, tbl_wr_tag, tbl_wr_node, tbl_wr_demote} = uq_head_q;

  // The ray's id and validity travel beside the table's lookup (LookupCycles cycles).
  logic [LookupCycles-1:0]               d_valid_q, d_invalid_q;
  logic [LookupCycles-1:0][IdWidth-1:0]  d_id_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      d_valid_q   <= '0;
      d_invalid_q <= '0;
      d_id_q      <= '0;
    end else begin
      d_valid_q   <= {d_valid_q[LookupCycles-2:0], hd_go};
      d_invalid_q <= {d_invalid_q[LookupCycles-2:0], hd_invalid};
      d_id_q      <= {d_id_q[LookupCycles-2:0], hd_id};
    end
  end
  localparam int unsigned DLast = LookupCycles - 1;
  assign lk_due_o = d_valid_q[DLast] && !d_invalid_q[DLast];

  // ---------------------------------------------------------------------------------------------
  // Prediction FIFO; rays are accepted only while every ray in flight (A, the hash, B, the lookup
  // queue, the lookup) has a FIFO place.
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned PredWidth = IdWidth + 1 + CountWidth + NodesPerEntry * NodeIdWidth;
  logic [PredWidth-1:0]      pred_out;
  logic                      pred_empty;
  logic [PredCountWidth-1:0] pred_count;
  logic [PredCountWidth:0]   in_flight;

  hrpp_fifo #(.Depth(PredFifoDepth), .Width(PredWidth)) u_pred_fifo (
    .clk_i, .rst_ni,
    .push_i(d_valid_q[DLast]),
    .data_i({d_id_q[DLast], d_invalid_q[DLast], lk_count_i, lk_nodes_i}),
    .pop_i(pred_valid_o && pred_ready_i), .data_o(pred_out),
    .empty_o(pred_empty), .full_o(), .count_o(pred_count)
  );
  assign pred_valid_o = !pred_empty;
  assign {pred_id_o, pred_invalid_o, pred_count_o, pred_nodes_o} = pred_out;

  // Confidence (ConfBits = 1): whether each ray in flight was given a prediction (a count > 0,
  // after the table's confidence gating), by id, written as its lookup result enters the
  // prediction FIFO and read with its final outcome's key. A ray given a prediction whose final
  // outcome has no hit demotes its entry (the skip controller; docs/predictor.md, "One ray",
  // step 6). KeyStoreBram = 0: read combinationally at ksf_id (the outcome's id as it enters F0).
  // KeyStoreBram = 1: read as the key store is, when K takes the outcome (at outcome_id_i, into a
  // register beside K), so that the deep memory's read multiplexer ends at a register and F0's
  // handshake starts at one. The entry was written when the ray's prediction entered the FIFO,
  // at least a cycle before the prediction can leave it, so before the ray's outcome can reach
  // the port; an id is reused only after its outcome left F0, so the register holds the entry's
  // value while the outcome waits in K.
  logic ksf_pred;
  if (ConfBits > 0) begin : gen_pred_given
    (* ram_style = "distributed" *) logic pg_mem_q[2**IdWidth];
    always_ff @(posedge clk_i) begin
      if (d_valid_q[DLast]) pg_mem_q[d_id_q[DLast]] <= lk_count_i != '0;
    end
    if (!KeyStoreBram) begin : gen_pg_comb
      assign ksf_pred = pg_mem_q[ksf_id];
    end else begin : gen_pg_k
      logic pg_k_q, pg_j_q;  // K's outcome's bit; with KeyStoreReg, J's
      always_ff @(posedge clk_i or negedge rst_ni) begin
        if (!rst_ni) begin
          pg_k_q <= 1'b0;
          pg_j_q <= 1'b0;
        end else begin
          if (ks_outcome_load[0]) pg_k_q <= pg_mem_q[outcome_id_i];
          if (ks_outcome_load[1]) pg_j_q <= pg_k_q;
        end
      end
      assign ksf_pred = KeyStoreReg ? pg_j_q : pg_k_q;
    end
  end else begin : gen_no_pred_given
    assign ksf_pred = 1'b0;
  end

  always_comb begin
    in_flight = (PredCountWidth + 1)'(a_valid_q) + (PredCountWidth + 1)'(b_valid_q) +
                (PredCountWidth + 1)'(lq_count);
    for (int i = 0; i < HashLatency; i++) in_flight += (PredCountWidth + 1)'(h_valid_q[i]);
    for (int i = 0; i < LookupCycles; i++) in_flight += (PredCountWidth + 1)'(d_valid_q[i]);
  end
  assign ray_ready_o = init_done && (in_flight + (PredCountWidth + 1)'(pred_count)) <
                                    (PredCountWidth + 1)'(PredFifoDepth);

  // ---------------------------------------------------------------------------------------------
  // Skip controller
  // ---------------------------------------------------------------------------------------------
  hrpp_skip_ctrl #(
    .IdWidth(IdWidth), .IdxWidth(IdxWidth), .TagWidth(TagWidth), .NodeIdWidth(NodeIdWidth),
    .FifoDepth(SkipFifoDepth), .ConfBits(ConfBits)
  ) u_skip (
    .clk_i, .rst_ni, .enable_i(init_done), .cfg_mode_i,
    .pw_valid_i(sc_pw_valid), .pw_ready_o(sc_pw_ready), .pw_id_i(sc_pw_id),
    .pw_hit_i(sc_pw_hit), .pw_node_i(sc_pw_node),
    .outcome_valid_i(sc_outcome_valid), .outcome_ready_o(sc_outcome_ready),
    .outcome_id_i(sc_outcome_id), .outcome_hit_i(sc_outcome_hit),
    .outcome_node_i(sc_outcome_node),
    .ksp_id_o(ksp_id), .ksp_idx_i(ksp_idx), .ksp_tag_i(ksp_tag), .ksp_any_hit_i(ksp_any_hit),
    .ksf_id_o(ksf_id), .ksf_idx_i(ksf_idx), .ksf_tag_i(ksf_tag), .ksf_pred_i(ksf_pred),
    .tbl_wr_valid_o(sc_tbl_wr_valid), .tbl_wr_ready_i(uq_room1), .tbl_wr_idx_o(sc_tbl_wr_idx),
    .tbl_wr_tag_o(sc_tbl_wr_tag), .tbl_wr_node_o(sc_tbl_wr_node),
    .tbl_wr_demote_o(sc_tbl_wr_demote),
    .tbl_wr2_valid_o(sc_tbl_wr2_valid), .tbl_wr2_ready_i(uq_room2),
    .tbl_wr2_idx_o(sc_tbl_wr2_idx), .tbl_wr2_tag_o(sc_tbl_wr2_tag),
    .tbl_wr2_node_o(sc_tbl_wr2_node),
    .skip_valid_o, .skip_ready_i, .skip_id_o, .skip_action_o
  );

  // ---------------------------------------------------------------------------------------------
  // Assertions
  // ---------------------------------------------------------------------------------------------
  // A ray accepted in cycle c is in A in c+1, then the hash's stages, B (the table's read), the
  // lookup's stages, and at the prediction FIFO's head: the latency hrpp_pkg declares (with the
  // lookup queue: when no other lane's request for the same bank is taken first).
  localparam int unsigned Stages = 1 + HashLatency + 1 + LookupCycles + 1;
  if (Stages != PredictionLatency + LookupCycles - LookupLatency) begin : gen_latency_check
    $error("hrpp_lane predicts in %0d cycles; hrpp_pkg declares %0d", Stages,
           PredictionLatency + LookupCycles - LookupLatency);
  end
  if (KeyStoreReg && !KeyStoreBram) begin : gen_ks_reg_check
    $error("KeyStoreReg needs KeyStoreBram (the register is the key store's block-RAM output)");
  end
  if (ConfBits > 1) begin : gen_conf_check
    $error("ConfBits %0d: the RTL has 0 or 1 confidence bits per way", ConfBits);
  end
  if (UpdateQueueDepth < 2 || (UpdateQueueDepth & (UpdateQueueDepth - 1)) != 0)
  begin : gen_update_queue_check
    $error("UpdateQueueDepth %0d is not a power of two >= 2", UpdateQueueDepth);
  end

`ifndef SYNTHESIS
  // The interfaces.
  PredKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      pred_valid_o |-> !$isunknown({pred_id_o, pred_invalid_o, pred_count_o, pred_nodes_o}));
  PredStable_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      pred_valid_o && !pred_ready_i |=> pred_valid_o &&
      $stable({pred_id_o, pred_invalid_o, pred_count_o, pred_nodes_o}));
  // The update queue never overflows nor underflows.
  UpdateQueueBounds_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      uq_count_q <= UqCountWidth'(UpdateQueueDepth) && (!uq_pop || uq_count_q != '0));
  // The registered head is the head entry.
  uq_req_t uq_head_stored;
  assign uq_head_stored = uq_mem_q[uq_rd_q];
  UpdateQueueHead_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      uq_count_q != '0 |-> uq_head_q == uq_head_stored);
  // The registered pointers and the one-hot count agree with the pointers and the count.
  UpdateQueueCopies_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      uq_rd1_q == uq_rd_q + 1'b1 && uq_wr_oh_q == UpdateQueueDepth'(1) << uq_wr_q &&
      uq_wr1_oh_q == UpdateQueueDepth'(1) << UqPtrWidth'(uq_wr_q + 1'b1) &&
      uq_cnt_oh_q == (UpdateQueueDepth + 1)'(1) << uq_count_q &&
      uq_wr_q == uq_rd_q + UqPtrWidth'(uq_count_q));
  // The head's next value is the entry at the next read pointer after this cycle's writes, as
  // the pointers say, whenever the queue holds one after this cycle.
  function automatic uq_req_t uq_entry_after_writes(logic [UqPtrWidth-1:0] i, uq_req_t stored);
    if (uq_take1 && uq_wr_q == i) return uq_req1;
    if (uq_take2 && uq_wr_q + 1'b1 == i) return uq_req2;
    return stored;
  endfunction
  logic [UqPtrWidth-1:0] uq_rd_plus1;
  uq_req_t               uq_behind_stored;
  logic                  uq_empty_next;
  assign uq_rd_plus1      = uq_rd_q + 1'b1;
  assign uq_behind_stored = uq_mem_q[uq_rd_plus1];
  assign uq_empty_next    = uq_count_q + UqCountWidth'(uq_take1) + UqCountWidth'(uq_take2) ==
                            UqCountWidth'(uq_pop);
  UpdateQueueHeadNext_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !uq_empty_next |-> (uq_pop ? uq_head_if_pop ==
                                   uq_entry_after_writes(uq_rd_plus1, uq_behind_stored) :
                                   uq_head_if_hold ==
                                   uq_entry_after_writes(uq_rd_q, uq_head_q)));
  ReadyKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !$isunknown({ray_ready_o, pw_ready_o, outcome_ready_o, pred_valid_o, skip_valid_o}));
`endif

endmodule

`default_nettype wire
