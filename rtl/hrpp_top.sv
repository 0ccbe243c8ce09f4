`default_nettype none
// HRPP top: hash unit, predictor table and skip controller between a traversal engine's ray
// stream and its predicted / root walks (docs/microarchitecture.md has the interfaces, the
// pipeline and a timing diagram).
//
//   rays in ──> [A: input regs] ─hash (3 stages)─> [B: key regs, key store write, table lookup]
//               ─> table (4 cycles) ─> prediction FIFO ──> predictions out
//   predicted-walk results, final outcomes in ──> skip controller ──> update queue ──> table
//                                                                 └──> skip decisions out
//
// Everything but the table is one lane (rtl/hrpp_lane.sv, which hrpp_lanes instantiates Lanes
// times around a banked table); here its lookups and updates go straight to one hrpp_pred_table.
// All outputs come from registers or FIFO heads; ready outputs depend on state only.
module hrpp_top
  import hrpp_pkg::*;
#(
  // Hash (docs/hash.md). Every default is the default configuration's
  // (rtl/config/hrpp_configs.json, through hrpp_pkg).
  parameter hash_variant_e Variant = DefaultVariant,
  parameter int unsigned Precision = DefaultPrecision,
  parameter int unsigned ExpBits = DefaultExpBits,
  parameter int unsigned OriginBits = DefaultOriginBits,
  parameter int unsigned DirBits = DefaultDirBits,
  parameter combine_e Combine = DefaultCombine,
  parameter dir_code_e DirCode = DefaultDirCode,  /// improved: direction grid or octahedral
  // Table
  parameter int unsigned NumSets = DefaultNumSets,              /// sets, a power of two
  parameter int unsigned NumWays = DefaultNumWays,              /// ways, 2..16
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
  parameter bit InjectFault = DefaultInjectFault,  /// test only: a one-bit fault in the table
  parameter int unsigned ConfBits = DefaultConfBits,  /// confidence bit per table way: 0 or 1
  parameter bit IssueReg = DefaultIssueReg,  /// the table's issue register (+1 cycle of update)
  localparam int unsigned IdxWidth = $clog2(NumSets),
  localparam int unsigned CountWidth = $clog2(NodesPerEntry + 1)
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
  output logic [CountWidth-1:0]                      pred_count_o,    /// 0: no prediction
  output logic [NodesPerEntry-1:0][NodeIdWidth-1:0]  pred_nodes_o,    /// MRU first
  // Predicted-walk results from the traversal engine (one per ray)
  input  logic                                       pw_valid_i,
  output logic                                       pw_ready_o,
  input  logic [IdWidth-1:0]                         pw_id_i,
  input  logic                                       pw_hit_i,     /// a predicted subtree hit
  input  logic [NodeIdWidth-1:0]                     pw_node_i,    /// ... this one
  // Final outcomes from the traversal engine (rays not skipped)
  input  logic                                       outcome_valid_i,
  output logic                                       outcome_ready_o,
  input  logic [IdWidth-1:0]                         outcome_id_i,
  input  logic                                       outcome_hit_i,   /// write outcome_node_i
  input  logic [NodeIdWidth-1:0]                     outcome_node_i,  /// node to insert/refresh
  // Skip decisions
  output logic                                       skip_valid_o,
  input  logic                                       skip_ready_i,
  output logic [IdWidth-1:0]                         skip_id_o,
  output action_e                                    skip_action_o
);

  logic init_done;

  // ---------------------------------------------------------------------------------------------
  // The lane (rtl/hrpp_lane.sv): input registers, hash, key store, skip controller, prediction
  // and skip FIFOs, update queue; its lookups go straight to the table, which takes every one.
  // ---------------------------------------------------------------------------------------------
  logic                                      lk_req, lk_due, lk_valid;
  logic [IdxWidth-1:0]                       lk_idx;
  logic [TagWidth-1:0]                       lk_tag;
  logic [CountWidth-1:0]                     lk_count;
  logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes;
  logic                                      tbl_wr_valid, tbl_wr_ready, tbl_wr_demote;
  logic [IdxWidth-1:0]                       tbl_wr_idx;
  logic [TagWidth-1:0]                       tbl_wr_tag;
  logic [NodeIdWidth-1:0]                    tbl_wr_node;

  hrpp_lane #(
    .Variant(Variant), .Precision(Precision), .ExpBits(ExpBits), .OriginBits(OriginBits),
    .DirBits(DirBits), .Combine(Combine), .DirCode(DirCode),
    .NumSets(NumSets), .NodesPerEntry(NodesPerEntry), .NodeIdWidth(NodeIdWidth),
    .TagWidth(TagWidth), .IdWidth(IdWidth), .KeyStoreBram(KeyStoreBram),
    .KeyStoreReg(KeyStoreReg), .PredFifoDepth(PredFifoDepth), .SkipFifoDepth(SkipFifoDepth),
    .UpdateQueueDepth(UpdateQueueDepth), .ConfBits(ConfBits), .LookupQueue(1'b0)
  ) u_lane (
    .clk_i, .rst_ni, .init_done_i(init_done), .cfg_mode_i, .cfg_cell_exp_i,
    .ray_valid_i, .ray_ready_o, .ray_id_i, .ray_kind_i, .ray_org_i, .ray_dir_i,
    .pred_valid_o, .pred_ready_i, .pred_id_o, .pred_invalid_o, .pred_count_o, .pred_nodes_o,
    .pw_valid_i, .pw_ready_o, .pw_id_i, .pw_hit_i, .pw_node_i,
    .outcome_valid_i, .outcome_ready_o, .outcome_id_i, .outcome_hit_i, .outcome_node_i,
    .skip_valid_o, .skip_ready_i, .skip_id_o, .skip_action_o,
    .lk_valid_o(lk_req), .lk_ready_i(1'b1), .lk_idx_o(lk_idx), .lk_tag_o(lk_tag),
    .lk_due_o(lk_due), .lk_count_i(lk_count), .lk_nodes_i(lk_nodes),
    .tbl_wr_valid_o(tbl_wr_valid), .tbl_wr_ready_i(tbl_wr_ready), .tbl_wr_idx_o(tbl_wr_idx),
    .tbl_wr_tag_o(tbl_wr_tag), .tbl_wr_node_o(tbl_wr_node), .tbl_wr_demote_o(tbl_wr_demote)
  );

  // ---------------------------------------------------------------------------------------------
  // Table
  // ---------------------------------------------------------------------------------------------
  hrpp_pred_table #(
    .NumSets(NumSets), .NumWays(NumWays), .NodesPerEntry(NodesPerEntry),
    .NodeIdWidth(NodeIdWidth), .TagWidth(TagWidth), .InjectFault(InjectFault),
    .ConfBits(ConfBits), .IssueReg(IssueReg)
  ) u_table (
    .clk_i, .rst_ni, .init_done_o(init_done),
    .lk_valid_i(lk_req), .lk_idx_i(lk_idx), .lk_tag_i(lk_tag),
    .lk_valid_o(lk_valid), .lk_count_o(lk_count), .lk_nodes_o(lk_nodes),
    .tbl_wr_valid_i(tbl_wr_valid), .tbl_wr_ready_o(tbl_wr_ready), .tbl_wr_idx_i(tbl_wr_idx),
    .tbl_wr_tag_i(tbl_wr_tag), .tbl_wr_node_i(tbl_wr_node), .tbl_wr_demote_i(tbl_wr_demote)
  );

`ifndef SYNTHESIS
  // The table answers exactly when the lane's id pipeline says it should.
  LookupAligned_A: assert property (@(posedge clk_i) disable iff (!rst_ni) lk_valid == lk_due);
`endif

endmodule

`default_nettype wire
