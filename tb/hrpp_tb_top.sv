`default_nettype none
// Simulation top of tb_hrpp: hrpp_top with its two configuration inputs taken from registers, as
// a configuration register block would drive them. The design requires the configuration to be
// held stable while rays are in flight, and tb_hrpp sets it before reset and never changes it,
// so the register changes no output of any cycle (the outputs are compared with the cycle model
// on every cycle, as before). Why it is here: Verilator evaluates all logic that reads a
// top-level input again on every eval() call, twice per clock cycle; the hash's first stage
// reads cfg_cell_exp_i, so without the register the whole stage ran three times per cycle
// (docs/results.md, "Performance"). Ports and parameters are hrpp_top's, except that Variant,
// Combine and DirCode are their enumerations' encodings: Verilator's -G cannot set an enum-typed
// parameter (the Verilator builds and lints take this top; rtl/config/hrpp_config.py writes their
// -G flags).
// Lanes > 1 (rtl/hrpp_lanes.sv): every interface is an array of Lanes; with one lane the arrays
// have one element and the top is hrpp_top as before (the same ports, bit for bit).
module hrpp_tb_top
  import hrpp_pkg::*;
#(
  parameter bit Variant = DefaultVariant,  /// hash_variant_e's encoding
  parameter int unsigned Precision = DefaultPrecision,
  parameter int unsigned ExpBits = DefaultExpBits,
  parameter int unsigned OriginBits = DefaultOriginBits,
  parameter int unsigned DirBits = DefaultDirBits,
  parameter bit Combine = DefaultCombine,  /// combine_e's encoding
  parameter bit DirCode = DefaultDirCode,  /// dir_code_e's encoding
  parameter int unsigned NumSets = DefaultNumSets,
  parameter int unsigned NumWays = DefaultNumWays,
  parameter int unsigned NodesPerEntry = DefaultNodesPerEntry,
  parameter int unsigned NodeIdWidth = DefaultNodeIdWidth,
  parameter int unsigned TagWidth = DefaultTagWidth,
  parameter int unsigned IdWidth = DefaultIdWidth,
  parameter int unsigned PredFifoDepth = DefaultPredFifoDepth,
  parameter int unsigned SkipFifoDepth = DefaultSkipFifoDepth,
  parameter int unsigned UpdateQueueDepth = DefaultUpdateQueueDepth,
  parameter bit KeyStoreBram = DefaultKeyStoreBram,
  parameter bit KeyStoreReg = DefaultKeyStoreReg,
  parameter bit InjectFault = DefaultInjectFault,
  parameter int unsigned ConfBits = DefaultConfBits,
  parameter bit IssueReg = DefaultIssueReg,
  parameter int unsigned Lanes = 1,  /// 1: hrpp_top; 2 or 4: hrpp_lanes (ports per lane)
  localparam int unsigned CountWidth = $clog2(NodesPerEntry + 1)
) (
  input  logic                                                 clk_i,
  input  logic                                                 rst_ni,
  input  mode_e                                                cfg_mode_i,
  input  logic signed [8:0]                                    cfg_cell_exp_i,
  input  logic [Lanes-1:0]                                     ray_valid_i,
  output logic [Lanes-1:0]                                     ray_ready_o,
  input  logic [Lanes-1:0][IdWidth-1:0]                        ray_id_i,
  input  logic [Lanes-1:0][2:0]                                ray_kind_i,
  input  logic [Lanes-1:0][2:0][31:0]                          ray_org_i,
  input  logic [Lanes-1:0][2:0][31:0]                          ray_dir_i,
  output logic [Lanes-1:0]                                     pred_valid_o,
  input  logic [Lanes-1:0]                                     pred_ready_i,
  output logic [Lanes-1:0][IdWidth-1:0]                        pred_id_o,
  output logic [Lanes-1:0]                                     pred_invalid_o,
  output logic [Lanes-1:0][CountWidth-1:0]                     pred_count_o,
  output logic [Lanes-1:0][NodesPerEntry-1:0][NodeIdWidth-1:0] pred_nodes_o,
  input  logic [Lanes-1:0]                                     pw_valid_i,
  output logic [Lanes-1:0]                                     pw_ready_o,
  input  logic [Lanes-1:0][IdWidth-1:0]                        pw_id_i,
  input  logic [Lanes-1:0]                                     pw_hit_i,
  input  logic [Lanes-1:0][NodeIdWidth-1:0]                    pw_node_i,
  input  logic [Lanes-1:0]                                     outcome_valid_i,
  output logic [Lanes-1:0]                                     outcome_ready_o,
  input  logic [Lanes-1:0][IdWidth-1:0]                        outcome_id_i,
  input  logic [Lanes-1:0]                                     outcome_hit_i,
  input  logic [Lanes-1:0][NodeIdWidth-1:0]                    outcome_node_i,
  output logic [Lanes-1:0]                                     skip_valid_o,
  input  logic [Lanes-1:0]                                     skip_ready_i,
  output logic [Lanes-1:0][IdWidth-1:0]                        skip_id_o,
  output action_e [Lanes-1:0]                                  skip_action_o
);

  // Loaded on every clock edge, in reset too (tb_hrpp clocks twice in its initial reset).
  mode_e             cfg_mode_q;
  logic signed [8:0] cfg_cell_exp_q;
  always_ff @(posedge clk_i) begin
    cfg_mode_q     <= cfg_mode_i;
    cfg_cell_exp_q <= cfg_cell_exp_i;
  end

  if (Lanes == 1) begin : gen_one_lane
    hrpp_top #(
      .Variant(hash_variant_e'(Variant)), .Precision(Precision), .ExpBits(ExpBits),
      .OriginBits(OriginBits), .DirBits(DirBits), .Combine(combine_e'(Combine)),
      .DirCode(dir_code_e'(DirCode)),
      .NumSets(NumSets), .NumWays(NumWays), .NodesPerEntry(NodesPerEntry),
      .NodeIdWidth(NodeIdWidth), .TagWidth(TagWidth), .IdWidth(IdWidth),
      .PredFifoDepth(PredFifoDepth), .SkipFifoDepth(SkipFifoDepth),
      .UpdateQueueDepth(UpdateQueueDepth), .KeyStoreBram(KeyStoreBram), .InjectFault(InjectFault),
      .KeyStoreReg(KeyStoreReg),
      .ConfBits(ConfBits), .IssueReg(IssueReg)
    ) u_dut (
      .clk_i, .rst_ni, .cfg_mode_i(cfg_mode_q), .cfg_cell_exp_i(cfg_cell_exp_q),
      .ray_valid_i(ray_valid_i[0]), .ray_ready_o(ray_ready_o[0]), .ray_id_i(ray_id_i[0]),
      .ray_kind_i(ray_kind_i[0]), .ray_org_i(ray_org_i[0]), .ray_dir_i(ray_dir_i[0]),
      .pred_valid_o(pred_valid_o[0]), .pred_ready_i(pred_ready_i[0]), .pred_id_o(pred_id_o[0]),
      .pred_invalid_o(pred_invalid_o[0]), .pred_count_o(pred_count_o[0]),
      .pred_nodes_o(pred_nodes_o[0]),
      .pw_valid_i(pw_valid_i[0]), .pw_ready_o(pw_ready_o[0]), .pw_id_i(pw_id_i[0]),
      .pw_hit_i(pw_hit_i[0]), .pw_node_i(pw_node_i[0]),
      .outcome_valid_i(outcome_valid_i[0]), .outcome_ready_o(outcome_ready_o[0]),
      .outcome_id_i(outcome_id_i[0]), .outcome_hit_i(outcome_hit_i[0]),
      .outcome_node_i(outcome_node_i[0]),
      .skip_valid_o(skip_valid_o[0]), .skip_ready_i(skip_ready_i[0]), .skip_id_o(skip_id_o[0]),
      .skip_action_o(skip_action_o[0])
    );
  end else begin : gen_lanes
    hrpp_lanes #(
      .Variant(hash_variant_e'(Variant)), .Precision(Precision), .ExpBits(ExpBits),
      .OriginBits(OriginBits), .DirBits(DirBits), .Combine(combine_e'(Combine)),
      .DirCode(dir_code_e'(DirCode)),
      .NumSets(NumSets), .NumWays(NumWays), .NodesPerEntry(NodesPerEntry),
      .NodeIdWidth(NodeIdWidth), .TagWidth(TagWidth), .IdWidth(IdWidth),
      .PredFifoDepth(PredFifoDepth), .SkipFifoDepth(SkipFifoDepth),
      .UpdateQueueDepth(UpdateQueueDepth), .KeyStoreBram(KeyStoreBram), .InjectFault(InjectFault),
      .KeyStoreReg(KeyStoreReg),
      .ConfBits(ConfBits), .IssueReg(IssueReg), .Lanes(Lanes)
    ) u_dut (
      .clk_i, .rst_ni, .cfg_mode_i(cfg_mode_q), .cfg_cell_exp_i(cfg_cell_exp_q),
      .ray_valid_i, .ray_ready_o, .ray_id_i, .ray_kind_i, .ray_org_i, .ray_dir_i,
      .pred_valid_o, .pred_ready_i, .pred_id_o, .pred_invalid_o, .pred_count_o, .pred_nodes_o,
      .pw_valid_i, .pw_ready_o, .pw_id_i, .pw_hit_i, .pw_node_i,
      .outcome_valid_i, .outcome_ready_o, .outcome_id_i, .outcome_hit_i, .outcome_node_i,
      .skip_valid_o, .skip_ready_i, .skip_id_o, .skip_action_o
    );
  end

endmodule

`default_nettype wire
