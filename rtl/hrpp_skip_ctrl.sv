`default_nettype none
// HRPP skip controller: takes the traversal engine's outcomes, decides whether a ray's walk from
// the root can be skipped, and issues the table updates (docs/microarchitecture.md).
//
// Two inputs, each registered (P0, F0, with the ray's set, tag and query type read from the key
// store by id as the message is accepted) and each able to take one message per cycle:
//   predicted-walk results (pw_*): the predicted subtrees were walked; hit_i = one of them hit
//     (node_i: which). Decision: ActSkip if the ray is an any-hit query or the mode is
//     ClosestSpec (node_i is then refreshed in the table), ActShrink in ClosestExact mode,
//     ActFull without a hit. Every ray gets exactly one.
//   final outcomes (outcome_*): the walk from the root is done; hit_i = write node_i to the table
//     (the verified predicted node, or the hit leaf's go-up ancestor); 0 = nothing to write.
// Up to two update requests per cycle, in this order: a final outcome's on the first port
// (tbl_wr_*, else the predicted-walk result's there), and a predicted-walk result's behind it on
// the second (tbl_wr2_*, only with a final outcome's on the first). tbl_wr_ready_i: room for
// one request; tbl_wr2_ready_i: room for two (it implies tbl_wr_ready_i). A message leaves its
// register when its decision fits in the output FIFO and its update is taken.
module hrpp_skip_ctrl
  import hrpp_pkg::*;
#(
  parameter int unsigned IdWidth = DefaultIdWidth,          /// ray id bits
  parameter int unsigned IdxWidth = $clog2(DefaultNumSets), /// set index bits
  parameter int unsigned TagWidth = DefaultTagWidth,        /// stored tag bits
  parameter int unsigned NodeIdWidth = DefaultNodeIdWidth,  /// node id bits
  parameter int unsigned FifoDepth = DefaultSkipFifoDepth,  /// skip decision FIFO entries
  parameter int unsigned ConfBits = DefaultConfBits         /// confidence bits: demotes if 1
) (
  input  logic                   clk_i,
  input  logic                   rst_ni,
  input  logic                   enable_i,      /// the table finished its reset clear
  input  mode_e                  cfg_mode_i,
  // Predicted-walk results from the traversal engine
  input  logic                   pw_valid_i,
  output logic                   pw_ready_o,
  input  logic [IdWidth-1:0]     pw_id_i,
  input  logic                   pw_hit_i,
  input  logic [NodeIdWidth-1:0] pw_node_i,
  // Final outcomes from the traversal engine
  input  logic                   outcome_valid_i,
  output logic                   outcome_ready_o,
  input  logic [IdWidth-1:0]     outcome_id_i,
  input  logic                   outcome_hit_i,
  input  logic [NodeIdWidth-1:0] outcome_node_i,
  // Key store reads (combinational) by the ids of the messages on the inputs
  output logic [IdWidth-1:0]     ksp_id_o,
  input  logic [IdxWidth-1:0]    ksp_idx_i,
  input  logic [TagWidth-1:0]    ksp_tag_i,
  input  logic                   ksp_any_hit_i,
  output logic [IdWidth-1:0]     ksf_id_o,
  input  logic [IdxWidth-1:0]    ksf_idx_i,
  input  logic [TagWidth-1:0]    ksf_tag_i,
  input  logic                   ksf_pred_i,  /// the outcome's ray was given a prediction
  // Table write requests (the table's update: node_o becomes the most recently used node)
  output logic                   tbl_wr_valid_o,
  input  logic                   tbl_wr_ready_i,
  output logic [IdxWidth-1:0]    tbl_wr_idx_o,
  output logic [TagWidth-1:0]    tbl_wr_tag_o,
  output logic [NodeIdWidth-1:0] tbl_wr_node_o,
  output logic                   tbl_wr_demote_o,  /// the first request is a demote
  output logic                   tbl_wr2_valid_o,  /// a second request, behind the first
  input  logic                   tbl_wr2_ready_i,  /// room for both requests
  output logic [IdxWidth-1:0]    tbl_wr2_idx_o,
  output logic [TagWidth-1:0]    tbl_wr2_tag_o,
  output logic [NodeIdWidth-1:0] tbl_wr2_node_o,
  // Skip decisions
  output logic                   skip_valid_o,
  input  logic                   skip_ready_i,
  output logic [IdWidth-1:0]     skip_id_o,
  output action_e                skip_action_o
);

  // P0 and F0: the registered messages and their rays' keys
  logic                   p0_valid_q, p0_hit_q, f0_valid_q, f0_hit_q;
  // P0's decision is taken as the result enters P0 (the mode is static): p0_skip_q = ActSkip, so
  // the table request (p_needs) starts at a register.
  logic                   p0_skip_q;
  logic                   f0_demote_q;  // ConfBits = 1: the outcome requests a demote
  logic [IdWidth-1:0]     p0_id_q;
  logic [IdxWidth-1:0]    p0_idx_q, f0_idx_q;
  logic [TagWidth-1:0]    p0_tag_q, f0_tag_q;
  logic [NodeIdWidth-1:0] p0_node_q, f0_node_q;

  action_e action;
  logic    fifo_full, fifo_empty, p_needs, f_req, p_req, p_advance, f_advance;

  assign ksp_id_o = pw_id_i;
  assign ksf_id_o = outcome_id_i;

  always_comb begin
    action = ActFull;
    if (p0_hit_q) action = p0_skip_q ? ActSkip : ActShrink;
  end

  // The table's request ports: a final outcome first, a predicted-walk result behind it.
  assign p_needs        = p0_skip_q;  // action == ActSkip
  // A final outcome requests an update when it hit, a demote (ConfBits = 1) when its ray was given
  // a prediction and missed: an outcome follows only a predicted-walk result without a hit
  // (ActFull; ActShrink's answer is at least the predicted hit, so its outcome hits), so the
  // prediction failed (docs/predictor.md, "One ray", step 6).
  assign f_req          = f0_valid_q && (f0_hit_q || f0_demote_q);
  assign p_req          = p0_valid_q && p_needs && !fifo_full;
  assign tbl_wr_valid_o = f_req || p_req;
  assign tbl_wr_idx_o   = f_req ? f0_idx_q : p0_idx_q;
  assign tbl_wr_tag_o   = f_req ? f0_tag_q : p0_tag_q;
  assign tbl_wr_node_o  = f_req ? f0_node_q : p0_node_q;
  assign tbl_wr_demote_o = f_req && f0_demote_q;
  assign tbl_wr2_valid_o = f_req && p_req;
  assign tbl_wr2_idx_o   = p0_idx_q;
  assign tbl_wr2_tag_o   = p0_tag_q;
  assign tbl_wr2_node_o  = p0_node_q;

  assign f_advance       = f0_valid_q && (!(f0_hit_q || f0_demote_q) || tbl_wr_ready_i);
  assign p_advance       = p0_valid_q && !fifo_full &&
                           (!p_needs || (f_req ? tbl_wr2_ready_i : tbl_wr_ready_i));
  assign pw_ready_o      = enable_i && (!p0_valid_q || p_advance);
  assign outcome_ready_o = enable_i && (!f0_valid_q || f_advance);

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      p0_valid_q   <= 1'b0;
      p0_id_q      <= '0;
      p0_hit_q     <= 1'b0;
      p0_node_q    <= '0;
      p0_idx_q     <= '0;
      p0_tag_q     <= '0;
      p0_skip_q    <= 1'b0;
      f0_valid_q   <= 1'b0;
      f0_hit_q     <= 1'b0;
      f0_demote_q  <= 1'b0;
      f0_node_q    <= '0;
      f0_idx_q     <= '0;
      f0_tag_q     <= '0;
    end else begin
      if (pw_ready_o) begin
        p0_valid_q   <= pw_valid_i;
        p0_id_q      <= pw_id_i;
        p0_hit_q     <= pw_hit_i;
        p0_node_q    <= pw_node_i;
        p0_idx_q     <= ksp_idx_i;
        p0_tag_q     <= ksp_tag_i;
        p0_skip_q    <= pw_hit_i && (ksp_any_hit_i || cfg_mode_i == ModeClosestSpec);
      end
      if (outcome_ready_o) begin
        f0_valid_q <= outcome_valid_i;
        f0_hit_q   <= outcome_hit_i;
        f0_demote_q <= ConfBits > 0 && ksf_pred_i && !outcome_hit_i;
        f0_node_q  <= outcome_node_i;
        f0_idx_q   <= ksf_idx_i;
        f0_tag_q   <= ksf_tag_i;
      end
    end
  end

  logic [IdWidth+1:0] fifo_out;
  hrpp_fifo #(.Depth(FifoDepth), .Width(IdWidth + 2)) u_fifo (
    .clk_i, .rst_ni,
    .push_i(p_advance), .data_i({p0_id_q, action}),
    .pop_i(skip_valid_o && skip_ready_i), .data_o(fifo_out),
    .empty_o(fifo_empty), .full_o(fifo_full), .count_o()
  );
  assign skip_valid_o  = !fifo_empty;
  assign skip_id_o     = fifo_out[IdWidth+1:2];
  assign skip_action_o = action_e'(fifo_out[1:0]);

  // ---------------------------------------------------------------------------------------------
  // Assertions
  // ---------------------------------------------------------------------------------------------
  // A predicted-walk result accepted in cycle t is in P0 in t+1 and at the skip FIFO's head in
  // t+2 (when it can advance at once): the decision latency hrpp_pkg declares.
  localparam int unsigned Stages = 2;
  if (Stages != DecisionLatency) begin : gen_latency_check
    $error("hrpp_skip_ctrl decides in %0d cycles; hrpp_pkg::DecisionLatency declares %0d", Stages,
           DecisionLatency);
  end

`ifndef SYNTHESIS
  SkipKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      skip_valid_o |-> !$isunknown({skip_id_o, skip_action_o}));
  SkipStable_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      skip_valid_o && !skip_ready_i |=> skip_valid_o && $stable({skip_id_o, skip_action_o}));
  // A message that needs the table port is never dropped: it advances only when accepted.
  NoDroppedUpdate_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      (f_advance && (f0_hit_q || f0_demote_q)) |-> tbl_wr_valid_o && tbl_wr_ready_i);
  if (ConfBits == 0) begin : gen_no_conf_check
    DemoteOnlyWithConfidence_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
        !f0_demote_q);
  end
  NoDroppedRefresh_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      (p_advance && p_needs) |-> (f_req ? tbl_wr2_valid_o && tbl_wr2_ready_i && tbl_wr_ready_i
                                        : tbl_wr_valid_o && tbl_wr_ready_i));
`endif

endmodule

`default_nettype wire
