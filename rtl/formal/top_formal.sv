`default_nettype none
// Formal harness of hrpp_top's credits and handshakes (docs/verification.md), on a small
// configuration (faithful hash of 1 exponent and 1 mantissa bit, 2 sets x 2 ways, one node per
// entry, 4 ray ids, an update queue of 2 entries) with the default prediction FIFO of 16 entries.
//
// Credits: the rays accepted and not yet taken as predictions (counted at the ports) equal the
// rays in flight in the pipeline (A, the hash stages, B, the lookup stages) plus the prediction
// FIFO's entries, and never exceed PredFifoDepth; the FIFO is never pushed when full.
//
// With MITER defined: no ready or valid output depends combinationally on an input. A second
// copy of the DUT gets the same inputs as the first until `diverge_i`, from then on its own
// free inputs; while every earlier cycle had the same inputs, both copies are in the same state,
// so their ready and valid outputs must agree whatever the inputs of the current cycle are.
module top_formal
  import hrpp_pkg::*;
#(
  parameter int unsigned PredFifoDepth = 16,
  parameter int unsigned IdWidth = 2,
  parameter int unsigned NodeIdWidth = 2
) (
  input logic                   clk_i,
  input logic [1:0]             mode_i,
  input logic signed [8:0]      cell_exp_i,
  input logic                   ray_valid_i,
  input logic [IdWidth-1:0]     ray_id_i,
  input logic [2:0]             ray_kind_i,
  input logic [2:0][31:0]       ray_org_i,
  input logic [2:0][31:0]       ray_dir_i,
  input logic                   pred_ready_i,
  input logic                   pw_valid_i,
  input logic [IdWidth-1:0]     pw_id_i,
  input logic                   pw_hit_i,
  input logic [NodeIdWidth-1:0] pw_node_i,
  input logic                   outcome_valid_i,
  input logic [IdWidth-1:0]     outcome_id_i,
  input logic                   outcome_hit_i,
  input logic [NodeIdWidth-1:0] outcome_node_i,
  input logic                   skip_ready_i,
  // the second copy's inputs (MITER), used from diverge_i on
  input logic                   diverge_i,
  input logic                   b_ray_valid_i,
  input logic                   b_pred_ready_i,
  input logic                   b_pw_valid_i,
  input logic                   b_outcome_valid_i,
  input logic                   b_skip_ready_i,
  input logic [IdWidth-1:0]     b_id_i
);
  localparam int unsigned CountWidth = $clog2(PredFifoDepth + 1);

  logic init_q = 1'b1;
  always_ff @(posedge clk_i) init_q <= 1'b0;
  logic rst_ni;
  assign rst_ni = !init_q;

  // The configuration is static: free inputs held at their first cycle's values (inputs, not
  // registers that keep their initial value, because the miter's zero initialization would fix
  // those).
  logic [1:0]        mode_q;
  logic signed [8:0] cell_exp_q;
  always_ff @(posedge clk_i) begin
    mode_q     <= mode_i;
    cell_exp_q <= cell_exp_i;
  end
  always_comb begin
    assume (mode_i <= 2'd2);
    if (rst_ni) assume (mode_i == mode_q && cell_exp_i == cell_exp_q);
  end

  logic                                ray_ready_o, pred_valid_o, pred_invalid_o, pw_ready_o;
  logic                                outcome_ready_o, skip_valid_o;
  logic [IdWidth-1:0]                  pred_id_o, skip_id_o;
  logic [0:0]                          pred_count_o;
  logic [0:0][NodeIdWidth-1:0]         pred_nodes_o;
  action_e                             skip_action_o;

  hrpp_top #(
    .Variant(HashFaithful), .Precision(1), .ExpBits(1), .Combine(CombineXor), .NumSets(2),
    .NumWays(2), .NodesPerEntry(1), .NodeIdWidth(NodeIdWidth), .TagWidth(2), .IdWidth(IdWidth),
    .PredFifoDepth(PredFifoDepth), .SkipFifoDepth(2), .UpdateQueueDepth(2), .KeyStoreBram(1'b0),
    .KeyStoreReg(1'b0),
    .InjectFault(1'b0), .ConfBits(0)
  ) dut (
    .clk_i, .rst_ni, .cfg_mode_i(mode_e'(mode_i)), .cfg_cell_exp_i(cell_exp_i),
    .ray_valid_i, .ray_ready_o, .ray_id_i, .ray_kind_i, .ray_org_i, .ray_dir_i,
    .pred_valid_o, .pred_ready_i, .pred_id_o, .pred_invalid_o, .pred_count_o, .pred_nodes_o,
    .pw_valid_i, .pw_ready_o, .pw_id_i, .pw_hit_i, .pw_node_i,
    .outcome_valid_i, .outcome_ready_o, .outcome_id_i, .outcome_hit_i, .outcome_node_i,
    .skip_valid_o, .skip_ready_i, .skip_id_o, .skip_action_o
  );

`ifndef MITER
  // Rays accepted and not yet taken as predictions.
  logic ray_acc, pred_acc;
  assign ray_acc  = ray_valid_i && ray_ready_o;
  assign pred_acc = pred_valid_o && pred_ready_i;
  logic [CountWidth:0] outstanding_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) outstanding_q <= '0;
    else outstanding_q <= outstanding_q + (CountWidth + 1)'(ray_acc) - (CountWidth + 1)'(pred_acc);
  end

  always_comb begin
    if (rst_ni) begin
      Credits_A: assert (outstanding_q <= (CountWidth + 1)'(PredFifoDepth));
      InFlight_A: assert (outstanding_q == (CountWidth + 1)'(dut.u_lane.in_flight) +
                                           (CountWidth + 1)'(dut.u_lane.pred_count));
      PredNoOverflow_A: assert (!dut.u_lane.d_valid_q[LookupLatency-1] ||
                                !dut.u_lane.u_pred_fifo.full_o);
      // Induction strengthening: the prediction FIFO's pointers agree with its count.
      PredFifo_A: assert (dut.u_lane.u_pred_fifo.count_q <= CountWidth'(PredFifoDepth) &&
                          dut.u_lane.u_pred_fifo.wr_q - dut.u_lane.u_pred_fifo.rd_q ==
                          dut.u_lane.u_pred_fifo.count_q[$clog2(PredFifoDepth)-1:0]);
      // ... and its registered flags (ab1b8be) with its count.
      PredFifoFlags_A: assert (dut.u_lane.u_pred_fifo.full_q ==
                               (dut.u_lane.u_pred_fifo.count_q == CountWidth'(PredFifoDepth)) &&
                               dut.u_lane.u_pred_fifo.empty_q ==
                               (dut.u_lane.u_pred_fifo.count_q == '0));
    end
  end
`else
  // The second copy: the same inputs until diverge_i, then partly its own (the handshake inputs
  // and the ids; the data inputs stay shared, which only narrows what may differ).
  logic diverged_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) diverged_q <= 1'b0;
    else if (diverge_i) diverged_q <= 1'b1;
  end
  logic d;
  assign d = diverge_i || diverged_q;

  logic                        b_ray_ready_o, b_pred_valid_o, b_pred_invalid_o, b_pw_ready_o;
  logic                        b_outcome_ready_o, b_skip_valid_o;
  logic [IdWidth-1:0]          b_pred_id_o, b_skip_id_o;
  logic [0:0]                  b_pred_count_o;
  logic [0:0][NodeIdWidth-1:0] b_pred_nodes_o;
  action_e                     b_skip_action_o;

  hrpp_top #(
    .Variant(HashFaithful), .Precision(1), .ExpBits(1), .Combine(CombineXor), .NumSets(2),
    .NumWays(2), .NodesPerEntry(1), .NodeIdWidth(NodeIdWidth), .TagWidth(2), .IdWidth(IdWidth),
    .PredFifoDepth(PredFifoDepth), .SkipFifoDepth(2), .UpdateQueueDepth(2), .KeyStoreBram(1'b0),
    .KeyStoreReg(1'b0),
    .InjectFault(1'b0), .ConfBits(0)
  ) dut_b (
    .clk_i, .rst_ni, .cfg_mode_i(mode_e'(mode_i)), .cfg_cell_exp_i(cell_exp_i),
    .ray_valid_i(d ? b_ray_valid_i : ray_valid_i), .ray_ready_o(b_ray_ready_o),
    .ray_id_i(d ? b_id_i : ray_id_i), .ray_kind_i, .ray_org_i, .ray_dir_i,
    .pred_valid_o(b_pred_valid_o), .pred_ready_i(d ? b_pred_ready_i : pred_ready_i),
    .pred_id_o(b_pred_id_o), .pred_invalid_o(b_pred_invalid_o), .pred_count_o(b_pred_count_o),
    .pred_nodes_o(b_pred_nodes_o),
    .pw_valid_i(d ? b_pw_valid_i : pw_valid_i), .pw_ready_o(b_pw_ready_o),
    .pw_id_i(d ? b_id_i : pw_id_i), .pw_hit_i, .pw_node_i,
    .outcome_valid_i(d ? b_outcome_valid_i : outcome_valid_i),
    .outcome_ready_o(b_outcome_ready_o), .outcome_id_i(d ? b_id_i : outcome_id_i),
    .outcome_hit_i, .outcome_node_i,
    .skip_valid_o(b_skip_valid_o), .skip_ready_i(d ? b_skip_ready_i : skip_ready_i),
    .skip_id_o(b_skip_id_o), .skip_action_o(b_skip_action_o)
  );

  always_comb begin
    if (rst_ni && !diverged_q) begin
      RayReadyComb_A: assert (ray_ready_o == b_ray_ready_o);
      PwReadyComb_A: assert (pw_ready_o == b_pw_ready_o);
      OutcomeReadyComb_A: assert (outcome_ready_o == b_outcome_ready_o);
      PredValidComb_A: assert (pred_valid_o == b_pred_valid_o);
      SkipValidComb_A: assert (skip_valid_o == b_skip_valid_o);
    end
  end
`endif
endmodule

`default_nettype wire
