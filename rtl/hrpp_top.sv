`default_nettype none
// HRPP top: hash unit, predictor table and skip controller between a traversal engine's ray
// stream and its predicted / root walks (docs/microarchitecture.md has the interfaces, the
// pipeline and a timing diagram).
//
//   rays in ──> [A: input regs] ─hash (2 stages)─> [B: key regs, key store write, table lookup]
//               ─> table (4 cycles) ─> prediction FIFO ──> predictions out
//   predicted-walk results, final outcomes in ──> skip controller ──> update queue ──> table
//                                                                 └──> skip decisions out
//
// All outputs come from registers or FIFO heads; ready outputs depend on state only.
module hrpp_top
  import hrpp_pkg::*;
#(
  // Hash (docs/hash.md)
  parameter bit Variant = 1'b0,                /// hash_variant_e: 0 faithful, 1 improved
  parameter int unsigned Precision = 6,
  parameter int unsigned ExpBits = 3,
  parameter int unsigned OriginBits = 5,
  parameter int unsigned DirBits = 3,
  parameter bit Combine = 1'b0,                /// combine_e: 0 xor, 1 concat
  // Table
  parameter int unsigned NumSets = 256,        /// sets, a power of two
  parameter int unsigned NumWays = 4,          /// ways, 2..16
  parameter int unsigned NodesPerEntry = 2,    /// node ids per way
  parameter int unsigned NodeIdWidth = 17,     /// bits of a BVH node id
  parameter int unsigned TagBits = 12,         /// stored tag bits (at most the full tag)
  // Interfaces
  parameter int unsigned IdWidth = 6,          /// ray id bits: rays in flight have distinct ids
  parameter int unsigned PredFifoDepth = 16,   /// prediction FIFO entries (a power of two)
  parameter int unsigned SkipFifoDepth = 4,    /// skip decision FIFO entries (a power of two)
  parameter bit InjectFault = 1'b0,            /// test only: a one-bit fault in the table
  localparam int unsigned IdxW = $clog2(NumSets),
  localparam int unsigned CountW = $clog2(NodesPerEntry + 1),
  localparam int unsigned FieldO = !Variant ? 1 + ExpBits + Precision : OriginBits,
  localparam int unsigned FieldD = !Variant ? 1 + ExpBits + Precision : DirBits,
  localparam int unsigned KeyWidth = !Combine ?
      (FieldO > FieldD ? 3 * FieldO : 3 * FieldD) : 3 * FieldO + 3 * FieldD
) (
  input  logic                                       clk_i,
  input  logic                                       rst_ni,
  // Configuration (hold stable while rays are in flight)
  input  mode_e                                      cfg_mode_i,
  input  logic signed [8:0]                          cfg_cell_exp_i,  /// improved hash cell size
  // Rays
  input  logic                                       ray_valid_i,
  output logic                                       ray_ready_o,
  input  logic [IdWidth-1:0]                         ray_id_i,
  input  logic [2:0]                                 ray_kind_i,
  input  logic [2:0][31:0]                           ray_org_i,
  input  logic [2:0][31:0]                           ray_dir_i,
  // Predictions
  output logic                                       pred_valid_o,
  input  logic                                       pred_ready_i,
  output logic [IdWidth-1:0]                         pred_id_o,
  output logic                                       pred_invalid_o,  /// infinite/NaN ray
  output logic [CountW-1:0]                          pred_count_o,    /// 0: no prediction
  output logic [NodesPerEntry-1:0][NodeIdWidth-1:0]  pred_nodes_o,    /// MRU first
  // Predicted-walk results from the traversal engine (one per ray)
  input  logic                                       pw_valid_i,
  output logic                                       pw_ready_o,
  input  logic [IdWidth-1:0]                         pw_id_i,
  input  logic                                       pw_hit_i,     /// a predicted subtree hit
  input  logic [NodeIdWidth-1:0]                     pw_node_i,    /// ... this one
  // Final outcomes from the traversal engine (rays not skipped)
  input  logic                                       upd_valid_i,
  output logic                                       upd_ready_o,
  input  logic [IdWidth-1:0]                         upd_id_i,
  input  logic                                       upd_hit_i,    /// write upd_node_i
  input  logic [NodeIdWidth-1:0]                     upd_node_i,   /// node to insert/refresh
  // Skip decisions
  output logic                                       skip_valid_o,
  input  logic                                       skip_ready_i,
  output logic [IdWidth-1:0]                         skip_id_o,
  output action_e                                    skip_action_o
);

  logic init_done;

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
  // Hash (three pipeline stages; id and query type travel beside it), then B: key registers
  // ---------------------------------------------------------------------------------------------
  logic [KeyWidth-1:0] key;
  logic                key_invalid;

  hrpp_hash #(
    .Variant(hash_variant_e'(Variant)), .Precision(Precision), .ExpBits(ExpBits),
    .OriginBits(OriginBits), .DirBits(DirBits), .Combine(combine_e'(Combine))
  ) u_hash (
    .clk_i, .rst_ni, .org_i(a_org_q), .dir_i(a_dir_q), .cell_exp_i(cfg_cell_exp_i),
    .key_o(key), .invalid_o(key_invalid)
  );

  localparam int unsigned HashLatency = 3;  // hrpp_hash's pipeline stages
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

  // Set index: XOR of all IdxW-bit chunks of the key; tag: the key above the index.
  logic [IdxW-1:0]    key_idx;
  logic [TagBits-1:0] key_tag;
  always_comb begin
    key_idx = '0;
    for (int i = 0; i < KeyWidth; i += IdxW) key_idx ^= IdxW'(key >> i);
    key_tag = TagBits'(key >> IdxW);
  end

  logic               b_valid_q, b_invalid_q, b_any_hit_q;
  logic [IdWidth-1:0] b_id_q;
  logic [IdxW-1:0]    b_idx_q;
  logic [TagBits-1:0] b_tag_q;

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

  // Key store: each in-flight ray's set, tag and query type, by id. Distributed RAM: it is read
  // combinationally as a message is accepted (in block RAM, the skip controller's registers
  // would become the RAM's output registers and its slow clock-to-output would start the
  // handshake paths).
  localparam int unsigned KsW = IdxW + TagBits + 1;
  (* ram_style = "distributed" *) logic [KsW-1:0] ks_mem_q[2**IdWidth];
  logic [IdWidth-1:0] ksp_id, ksf_id;  // the ids of the messages being accepted
  logic [IdxW-1:0]    ksp_idx, ksf_idx;
  logic [TagBits-1:0] ksp_tag, ksf_tag;
  logic               ksp_any_hit, ksf_any_hit_unused;

  always_ff @(posedge clk_i) begin
    if (b_valid_q) ks_mem_q[b_id_q] <= {b_idx_q, b_tag_q, b_any_hit_q};
  end
  assign {ksp_idx, ksp_tag, ksp_any_hit} = ks_mem_q[ksp_id];
  assign {ksf_idx, ksf_tag, ksf_any_hit_unused} = ks_mem_q[ksf_id];

  // ---------------------------------------------------------------------------------------------
  // Table
  // ---------------------------------------------------------------------------------------------
  logic                                      lk_valid;
  logic [CountW-1:0]                         lk_count;
  logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes;
  logic                                      up_valid, up_ready;
  logic [IdxW-1:0]                           up_idx;
  logic [TagBits-1:0]                        up_tag;
  logic [NodeIdWidth-1:0]                    up_node;
  // The skip controller's update requests, queued (U) before the table.
  logic                                      sc_up_valid, uq_full, uq_empty;
  logic [IdxW-1:0]                           sc_up_idx;
  logic [TagBits-1:0]                        sc_up_tag;
  logic [NodeIdWidth-1:0]                    sc_up_node;

  hrpp_pred_table #(
    .NumSets(NumSets), .NumWays(NumWays), .NodesPerEntry(NodesPerEntry),
    .NodeIdWidth(NodeIdWidth), .TagBits(TagBits), .InjectFault(InjectFault)
  ) u_table (
    .clk_i, .rst_ni, .init_done_o(init_done),
    .lk_valid_i(b_valid_q && !b_invalid_q), .lk_idx_i(b_idx_q), .lk_tag_i(b_tag_q),
    .lk_valid_o(lk_valid), .lk_count_o(lk_count), .lk_nodes_o(lk_nodes),
    .up_valid_i(up_valid), .up_ready_o(up_ready), .up_idx_i(up_idx), .up_tag_i(up_tag),
    .up_node_i(up_node)
  );

  // Update queue (two entries): the skip controller sees only whether it is full, so its
  // handshake does not wait for the table's same-set interlock, which looks at the queue's head.
  hrpp_fifo #(.Depth(2), .Width(IdxW + TagBits + NodeIdWidth)) u_update_fifo (
    .clk_i, .rst_ni,
    .push_i(sc_up_valid && !uq_full), .data_i({sc_up_idx, sc_up_tag, sc_up_node}),
    .pop_i(up_valid && up_ready), .data_o({up_idx, up_tag, up_node}),
    .empty_o(uq_empty), .full_o(uq_full), .count_o()
  );
  assign up_valid = !uq_empty;

  // The ray's id and validity travel beside the table's lookup (LookupLatency cycles).
  localparam int unsigned LookupLatency = 4;
  logic [LookupLatency-1:0]              d_valid_q, d_invalid_q;
  logic [LookupLatency-1:0][IdWidth-1:0] d_id_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      d_valid_q   <= '0;
      d_invalid_q <= '0;
      d_id_q      <= '0;
    end else begin
      d_valid_q   <= {d_valid_q[LookupLatency-2:0], b_valid_q};
      d_invalid_q <= {d_invalid_q[LookupLatency-2:0], b_invalid_q};
      d_id_q      <= {d_id_q[LookupLatency-2:0], b_id_q};
    end
  end
  localparam int unsigned DL = LookupLatency - 1;

  // ---------------------------------------------------------------------------------------------
  // Prediction FIFO; rays are accepted only while every ray in flight has a FIFO place.
  // ---------------------------------------------------------------------------------------------
  localparam int unsigned PredW = IdWidth + 1 + CountW + NodesPerEntry * NodeIdWidth;
  localparam int unsigned PredCountW = $clog2(PredFifoDepth + 1);
  logic [PredW-1:0]      pred_out;
  logic                  pred_empty;
  logic [PredCountW-1:0] pred_count;
  logic [PredCountW:0]   in_flight;

  hrpp_fifo #(.Depth(PredFifoDepth), .Width(PredW)) u_pred_fifo (
    .clk_i, .rst_ni,
    .push_i(d_valid_q[DL]), .data_i({d_id_q[DL], d_invalid_q[DL], lk_count, lk_nodes}),
    .pop_i(pred_valid_o && pred_ready_i), .data_o(pred_out),
    .empty_o(pred_empty), .full_o(), .count_o(pred_count)
  );
  assign pred_valid_o = !pred_empty;
  assign {pred_id_o, pred_invalid_o, pred_count_o, pred_nodes_o} = pred_out;

  always_comb begin
    in_flight = (PredCountW + 1)'(a_valid_q) + (PredCountW + 1)'(b_valid_q);
    for (int i = 0; i < HashLatency; i++) in_flight += (PredCountW + 1)'(h_valid_q[i]);
    for (int i = 0; i < LookupLatency; i++) in_flight += (PredCountW + 1)'(d_valid_q[i]);
  end
  assign ray_ready_o = init_done && (in_flight + (PredCountW + 1)'(pred_count)) <
                                    (PredCountW + 1)'(PredFifoDepth);

  // The table answers exactly when the id pipeline says it should.
`ifndef SYNTHESIS
  LookupAligned_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      lk_valid == (d_valid_q[DL] && !d_invalid_q[DL]));
`endif

  // ---------------------------------------------------------------------------------------------
  // Skip controller
  // ---------------------------------------------------------------------------------------------
  hrpp_skip_ctrl #(
    .IdWidth(IdWidth), .IdxW(IdxW), .TagBits(TagBits), .NodeIdWidth(NodeIdWidth),
    .FifoDepth(SkipFifoDepth)
  ) u_skip (
    .clk_i, .rst_ni, .enable_i(init_done), .cfg_mode_i,
    .pw_valid_i, .pw_ready_o, .pw_id_i, .pw_hit_i, .pw_node_i,
    .upd_valid_i, .upd_ready_o, .upd_id_i, .upd_hit_i, .upd_node_i,
    .ksp_id_o(ksp_id), .ksp_idx_i(ksp_idx), .ksp_tag_i(ksp_tag), .ksp_any_hit_i(ksp_any_hit),
    .ksf_id_o(ksf_id), .ksf_idx_i(ksf_idx), .ksf_tag_i(ksf_tag),
    .up_valid_o(sc_up_valid), .up_ready_i(!uq_full), .up_idx_o(sc_up_idx),
    .up_tag_o(sc_up_tag), .up_node_o(sc_up_node),
    .skip_valid_o, .skip_ready_i, .skip_id_o, .skip_action_o
  );

  // ---------------------------------------------------------------------------------------------
  // Interface assertions
  // ---------------------------------------------------------------------------------------------
`ifndef SYNTHESIS
  PredKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      pred_valid_o |-> !$isunknown({pred_id_o, pred_invalid_o, pred_count_o, pred_nodes_o}));
  PredStable_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      pred_valid_o && !pred_ready_i |=> pred_valid_o &&
      $stable({pred_id_o, pred_invalid_o, pred_count_o, pred_nodes_o}));
  ReadyKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      !$isunknown({ray_ready_o, pw_ready_o, upd_ready_o, pred_valid_o, skip_valid_o}));
`endif

endmodule

`default_nettype wire
