`default_nettype none
// Formal harness of hrpp_top's handshakes for every state (docs/verification.md, top.sby task
// prove_comb): no ready or valid output depends combinationally on an input, in any state, not
// only in the states reachable within a bounded depth.
//
// top_comb_gold and top_comb_gate are the same hrpp_top (the configuration of top_formal.sv) with
// the same ports; the gate's DUT takes its handshake and message inputs from the b_* ports, the
// gold's from the ordinary ones. top.sby's prove_comb script turns every flip-flop of both into
// an input and an output (`expose -evert-dff`), drops the next-state outputs, and builds a miter
// of the two (`miter -equiv`): both see one and the same arbitrary state and the same
// configuration and reset, each its own inputs, and their ready and valid outputs must agree.
// A state in which one of them depends on an input fails the check (one step, no unrolling).
module top_comb_core
  import hrpp_pkg::*;
#(
  parameter int unsigned PredFifoDepth = 16,
  parameter int unsigned IdWidth = 2,
  parameter int unsigned NodeIdWidth = 2,
  parameter bit KeyStoreBram = 1'b0,
  parameter bit KeyStoreReg = 1'b0,
  parameter bit Gate = 1'b0  // take the b_* inputs
) (
  input  logic                   clk_i,
  input  logic                   rst_ni,
  input  logic [1:0]             mode_i,
  input  logic signed [8:0]      cell_exp_i,
  input  logic                   ray_valid_i,
  input  logic [IdWidth-1:0]     ray_id_i,
  input  logic [2:0]             ray_kind_i,
  input  logic [2:0][31:0]       ray_org_i,
  input  logic [2:0][31:0]       ray_dir_i,
  input  logic                   pred_ready_i,
  input  logic                   pw_valid_i,
  input  logic [IdWidth-1:0]     pw_id_i,
  input  logic                   pw_hit_i,
  input  logic [NodeIdWidth-1:0] pw_node_i,
  input  logic                   outcome_valid_i,
  input  logic [IdWidth-1:0]     outcome_id_i,
  input  logic                   outcome_hit_i,
  input  logic [NodeIdWidth-1:0] outcome_node_i,
  input  logic                   skip_ready_i,
  input  logic                   b_ray_valid_i,
  input  logic [IdWidth-1:0]     b_ray_id_i,
  input  logic [2:0]             b_ray_kind_i,
  input  logic [2:0][31:0]       b_ray_org_i,
  input  logic [2:0][31:0]       b_ray_dir_i,
  input  logic                   b_pred_ready_i,
  input  logic                   b_pw_valid_i,
  input  logic [IdWidth-1:0]     b_pw_id_i,
  input  logic                   b_pw_hit_i,
  input  logic [NodeIdWidth-1:0] b_pw_node_i,
  input  logic                   b_outcome_valid_i,
  input  logic [IdWidth-1:0]     b_outcome_id_i,
  input  logic                   b_outcome_hit_i,
  input  logic [NodeIdWidth-1:0] b_outcome_node_i,
  input  logic                   b_skip_ready_i,
  output logic                   ray_ready_o,
  output logic                   pw_ready_o,
  output logic                   outcome_ready_o,
  output logic                   pred_valid_o,
  output logic                   skip_valid_o
);
  logic                        pred_invalid_o;
  logic [IdWidth-1:0]          pred_id_o, skip_id_o;
  logic [0:0]                  pred_count_o;
  logic [0:0][NodeIdWidth-1:0] pred_nodes_o;
  action_e                     skip_action_o;

  hrpp_top #(
    .Variant(HashFaithful), .Precision(1), .ExpBits(1), .Combine(CombineXor), .NumSets(2),
    .NumWays(2), .NodesPerEntry(1), .NodeIdWidth(NodeIdWidth), .TagWidth(2), .IdWidth(IdWidth),
    .PredFifoDepth(PredFifoDepth), .SkipFifoDepth(2), .UpdateQueueDepth(2),
    .KeyStoreBram(KeyStoreBram), .KeyStoreReg(KeyStoreReg), .InjectFault(1'b0), .ConfBits(0)
  ) dut (
    .clk_i, .rst_ni(1'b1), .cfg_mode_i(mode_e'(mode_i)), .cfg_cell_exp_i(cell_exp_i),
    .ray_valid_i(Gate ? b_ray_valid_i : ray_valid_i), .ray_ready_o,
    .ray_id_i(Gate ? b_ray_id_i : ray_id_i), .ray_kind_i(Gate ? b_ray_kind_i : ray_kind_i),
    .ray_org_i(Gate ? b_ray_org_i : ray_org_i), .ray_dir_i(Gate ? b_ray_dir_i : ray_dir_i),
    .pred_valid_o, .pred_ready_i(Gate ? b_pred_ready_i : pred_ready_i), .pred_id_o,
    .pred_invalid_o, .pred_count_o, .pred_nodes_o,
    .pw_valid_i(Gate ? b_pw_valid_i : pw_valid_i), .pw_ready_o,
    .pw_id_i(Gate ? b_pw_id_i : pw_id_i), .pw_hit_i(Gate ? b_pw_hit_i : pw_hit_i),
    .pw_node_i(Gate ? b_pw_node_i : pw_node_i),
    .outcome_valid_i(Gate ? b_outcome_valid_i : outcome_valid_i), .outcome_ready_o,
    .outcome_id_i(Gate ? b_outcome_id_i : outcome_id_i),
    .outcome_hit_i(Gate ? b_outcome_hit_i : outcome_hit_i),
    .outcome_node_i(Gate ? b_outcome_node_i : outcome_node_i),
    .skip_valid_o, .skip_ready_i(Gate ? b_skip_ready_i : skip_ready_i), .skip_id_o,
    .skip_action_o
  );
endmodule

module top_comb_gold #(
  parameter int unsigned PredFifoDepth = 16,
  parameter bit KeyStoreBram = 1'b0,
  parameter bit KeyStoreReg = 1'b0
) (
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic [1:0]        mode_i,
  input  logic signed [8:0] cell_exp_i,
  input  logic              ray_valid_i,
  input  logic [1:0]        ray_id_i,
  input  logic [2:0]        ray_kind_i,
  input  logic [2:0][31:0]  ray_org_i,
  input  logic [2:0][31:0]  ray_dir_i,
  input  logic              pred_ready_i,
  input  logic              pw_valid_i,
  input  logic [1:0]        pw_id_i,
  input  logic              pw_hit_i,
  input  logic [1:0]        pw_node_i,
  input  logic              outcome_valid_i,
  input  logic [1:0]        outcome_id_i,
  input  logic              outcome_hit_i,
  input  logic [1:0]        outcome_node_i,
  input  logic              skip_ready_i,
  input  logic              b_ray_valid_i,
  input  logic [1:0]        b_ray_id_i,
  input  logic [2:0]        b_ray_kind_i,
  input  logic [2:0][31:0]  b_ray_org_i,
  input  logic [2:0][31:0]  b_ray_dir_i,
  input  logic              b_pred_ready_i,
  input  logic              b_pw_valid_i,
  input  logic [1:0]        b_pw_id_i,
  input  logic              b_pw_hit_i,
  input  logic [1:0]        b_pw_node_i,
  input  logic              b_outcome_valid_i,
  input  logic [1:0]        b_outcome_id_i,
  input  logic              b_outcome_hit_i,
  input  logic [1:0]        b_outcome_node_i,
  input  logic              b_skip_ready_i,
  output logic              ray_ready_o,
  output logic              pw_ready_o,
  output logic              outcome_ready_o,
  output logic              pred_valid_o,
  output logic              skip_valid_o
);
  top_comb_core #(.PredFifoDepth(PredFifoDepth), .KeyStoreBram(KeyStoreBram),
                  .KeyStoreReg(KeyStoreReg), .Gate(1'b0)) core (.*);
endmodule

module top_comb_gate #(
  parameter int unsigned PredFifoDepth = 16,
  parameter bit KeyStoreBram = 1'b0,
  parameter bit KeyStoreReg = 1'b0
) (
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic [1:0]        mode_i,
  input  logic signed [8:0] cell_exp_i,
  input  logic              ray_valid_i,
  input  logic [1:0]        ray_id_i,
  input  logic [2:0]        ray_kind_i,
  input  logic [2:0][31:0]  ray_org_i,
  input  logic [2:0][31:0]  ray_dir_i,
  input  logic              pred_ready_i,
  input  logic              pw_valid_i,
  input  logic [1:0]        pw_id_i,
  input  logic              pw_hit_i,
  input  logic [1:0]        pw_node_i,
  input  logic              outcome_valid_i,
  input  logic [1:0]        outcome_id_i,
  input  logic              outcome_hit_i,
  input  logic [1:0]        outcome_node_i,
  input  logic              skip_ready_i,
  input  logic              b_ray_valid_i,
  input  logic [1:0]        b_ray_id_i,
  input  logic [2:0]        b_ray_kind_i,
  input  logic [2:0][31:0]  b_ray_org_i,
  input  logic [2:0][31:0]  b_ray_dir_i,
  input  logic              b_pred_ready_i,
  input  logic              b_pw_valid_i,
  input  logic [1:0]        b_pw_id_i,
  input  logic              b_pw_hit_i,
  input  logic [1:0]        b_pw_node_i,
  input  logic              b_outcome_valid_i,
  input  logic [1:0]        b_outcome_id_i,
  input  logic              b_outcome_hit_i,
  input  logic [1:0]        b_outcome_node_i,
  input  logic              b_skip_ready_i,
  output logic              ray_ready_o,
  output logic              pw_ready_o,
  output logic              outcome_ready_o,
  output logic              pred_valid_o,
  output logic              skip_valid_o
);
  top_comb_core #(.PredFifoDepth(PredFifoDepth), .KeyStoreBram(KeyStoreBram),
                  .KeyStoreReg(KeyStoreReg), .Gate(1'b1)) core (.*);
endmodule

`default_nettype wire
