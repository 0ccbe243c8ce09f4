`default_nettype none
// Formal harness of hrpp_skip_ctrl (docs/verification.md), on a small configuration (4 ray ids,
// 2 sets, 2-bit tags and nodes, the default skip FIFO of 4).
//
// One predicted-walk result, chosen arbitrarily among those accepted (track_i), is followed
// through P0 and the skip FIFO: it must leave as exactly one decision, at its turn, with its id
// and the action of the rule (ActSkip only for a hit of an any-hit query or in closest-spec mode,
// ActShrink for another hit, ActFull without one); only an ActSkip result writes the table (its
// node, set and tag, on the first request port, or on the second behind a final outcome's
// request in the same cycle). Every decision belongs to an accepted result: the results
// accepted minus the decisions taken equal P0 plus the FIFO's entries.
//
// The update queue's room for two requests (tbl_wr2_ready_i) implies room for one.
//
// With LIVE defined, the downstream is always ready (skip_ready_i, tbl_wr_ready_i,
// tbl_wr2_ready_i) and final outcomes come only for rays whose decision was taken and was not
// ActSkip, once each (the interface's id contract): then the tracked result's decision is taken
// at most Bound cycles after its acceptance, and every final outcome's update is taken in the
// cycle after it.
module skip_ctrl_formal
  import hrpp_pkg::*;
#(
  parameter int unsigned IdWidth = 2,
  parameter int unsigned IdxWidth = 1,
  parameter int unsigned TagWidth = 2,
  parameter int unsigned NodeIdWidth = 2,
  parameter int unsigned FifoDepth = 4,
  // Decision latency bound under LIVE: P0, a full FIFO, one final outcome per id that can be
  // waiting plus one per decision ahead, the FIFO ahead.
  parameter int unsigned Bound = 3 + (1 << IdWidth) + 2 * FifoDepth
) (
  input logic                   clk_i,
  input logic                   enable_rise_i,  // the table's reset clear ends
  input logic                   pw_valid_i,
  input logic [IdWidth-1:0]     pw_id_i,
  input logic                   pw_hit_i,
  input logic [NodeIdWidth-1:0] pw_node_i,
  input logic                   outcome_valid_i,
  input logic [IdWidth-1:0]     outcome_id_i,
  input logic                   outcome_hit_i,
  input logic [NodeIdWidth-1:0] outcome_node_i,
  input logic [IdxWidth-1:0]    ksp_idx_i,
  input logic [TagWidth-1:0]    ksp_tag_i,
  input logic                   ksp_any_hit_i,
  input logic [IdxWidth-1:0]    ksf_idx_i,
  input logic [TagWidth-1:0]    ksf_tag_i,
  input logic                   ksf_pred_i,  // free; ignored with ConfBits = 0
  input logic                   tbl_wr_ready_i,
  input logic                   tbl_wr2_ready_i,
  input logic                   skip_ready_i,
  input logic                   track_i
);
  localparam int unsigned CountWidth = $clog2(FifoDepth + 1);

  logic init_q = 1'b1;
  always_ff @(posedge clk_i) init_q <= 1'b0;
  logic rst_ni;
  assign rst_ni = !init_q;

  // The mode is static, and one of the three: a register without reset that keeps its initial
  // value, which the solver chooses (the slang front end ignores the anyconst attribute).
  logic [1:0] mode_raw;
  always_ff @(posedge clk_i) mode_raw <= mode_raw;
  mode_e cfg_mode_i;
  assign cfg_mode_i = mode_e'(mode_raw);
  always_comb assume (mode_raw <= 2'd2);

  // enable_i (hrpp_top: the table's init_done) rises once after reset and stays high.
  logic enable_i;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) enable_i <= 1'b0;
    else if (enable_rise_i) enable_i <= 1'b1;
  end

  logic                   pw_ready_o, outcome_ready_o, tbl_wr_valid_o, tbl_wr2_valid_o;
  logic                   tbl_wr_demote_o;  // never set with ConfBits = 0
  logic                   skip_valid_o;
  logic [IdWidth-1:0]     ksp_id_o, ksf_id_o, skip_id_o;
  logic [IdxWidth-1:0]    tbl_wr_idx_o, tbl_wr2_idx_o;
  logic [TagWidth-1:0]    tbl_wr_tag_o, tbl_wr2_tag_o;
  logic [NodeIdWidth-1:0] tbl_wr_node_o, tbl_wr2_node_o;
  action_e                skip_action_o;

  hrpp_skip_ctrl #(
    .IdWidth(IdWidth), .IdxWidth(IdxWidth), .TagWidth(TagWidth), .NodeIdWidth(NodeIdWidth),
    .FifoDepth(FifoDepth), .ConfBits(0)
  ) dut (.*);

  always_comb assume (!tbl_wr2_ready_i || tbl_wr_ready_i);

  logic pw_acc, outcome_acc, skip_acc, tbl_acc, tbl2_acc, p_write;
  assign pw_acc      = pw_valid_i && pw_ready_o;
  assign outcome_acc = outcome_valid_i && outcome_ready_o;
  assign skip_acc    = skip_valid_o && skip_ready_i;
  assign tbl_acc     = tbl_wr_valid_o && tbl_wr_ready_i;
  assign tbl2_acc    = tbl_wr2_valid_o && tbl_wr2_ready_i;
  // P0's request taken: alone on the first port, or on the second behind a final outcome's.
  assign p_write     = (tbl_acc && !dut.f_req) || (tbl2_acc && tbl_acc);

  function automatic action_e rule(logic hit, logic any_hit, mode_e mode);
    if (!hit) return ActFull;
    return any_hit || mode == ModeClosestSpec ? ActSkip : ActShrink;
  endfunction

  // Results accepted and not yet decided.
  logic [CountWidth:0] outstanding_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) outstanding_q <= '0;
    else outstanding_q <= outstanding_q + (CountWidth + 1)'(pw_acc) - (CountWidth + 1)'(skip_acc);
  end

  // The tracked result: 0 none, 1 in P0, 2 in the skip FIFO with ahead_q decisions before it.
  logic [1:0]             phase_q;
  logic [IdWidth-1:0]     t_id_q;
  logic                   t_hit_q, t_any_q;
  logic [NodeIdWidth-1:0] t_node_q;
  logic [IdxWidth-1:0]    t_idx_q;
  logic [TagWidth-1:0]    t_tag_q;
  logic [CountWidth-1:0]  ahead_q;
  logic [7:0]             age_q;
  action_e                t_action;
  assign t_action = rule(t_hit_q, t_any_q, cfg_mode_i);

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      phase_q  <= 2'd0;
      t_id_q   <= '0;
      t_hit_q  <= 1'b0;
      t_any_q  <= 1'b0;
      t_node_q <= '0;
      t_idx_q  <= '0;
      t_tag_q  <= '0;
      ahead_q  <= '0;
      age_q    <= '0;
    end else begin
      if (phase_q != 2'd0 && age_q != 8'hff) age_q <= age_q + 1'b1;
      case (phase_q)
        2'd0: if (pw_acc && track_i) begin
          phase_q  <= 2'd1;
          t_id_q   <= pw_id_i;
          t_hit_q  <= pw_hit_i;
          t_any_q  <= ksp_any_hit_i;
          t_node_q <= pw_node_i;
          t_idx_q  <= ksp_idx_i;
          t_tag_q  <= ksp_tag_i;
          age_q    <= '0;
        end
        2'd1: if (dut.p_advance) begin
          phase_q <= 2'd2;
          ahead_q <= dut.u_fifo.count_q - CountWidth'(skip_acc);
        end
        default: if (skip_acc) begin
          if (ahead_q == '0) phase_q <= 2'd0;
          else ahead_q <= ahead_q - 1'b1;
        end
      endcase
    end
  end

  always_comb begin
    if (rst_ni) begin
      // Exactly one decision per accepted result.
      Conserve_A: assert (outstanding_q == (CountWidth + 1)'(dut.p0_valid_q) +
                                           (CountWidth + 1)'(dut.u_fifo.count_q));
      // The tracked result's decision: its id, the rule's action, at its turn.
      if (phase_q == 2'd2 && ahead_q == '0 && skip_acc) begin
        DecisionId_A: assert (skip_id_o == t_id_q);
        DecisionAction_A: assert (skip_action_o == t_action);
        SkipOnlyHit_A: assert (skip_action_o != ActSkip ||
                               (t_hit_q && (t_any_q || cfg_mode_i == ModeClosestSpec)));
      end
      // Only an ActSkip result writes the table, with its node, set and tag, before it leaves P0.
      if (phase_q == 2'd1) begin
        if (p_write) begin
          WriteOnlySkip_A: assert (t_action == ActSkip);
        end
        if (tbl_acc && !dut.f_req) begin
          WriteData_A: assert (tbl_wr_node_o == t_node_q && tbl_wr_idx_o == t_idx_q &&
                               tbl_wr_tag_o == t_tag_q);
        end
        if (tbl2_acc) begin
          Write2Data_A: assert (tbl_acc && dut.f_req && tbl_wr2_node_o == t_node_q &&
                                tbl_wr2_idx_o == t_idx_q && tbl_wr2_tag_o == t_tag_q);
        end
        if (dut.p_advance && t_action == ActSkip) begin
          SkipWrites_A: assert (p_write);
        end
      end
      // The second port carries a request only behind a final outcome's on the first.
      Write2Behind_A: assert (!tbl_wr2_valid_o || (tbl_wr_valid_o && dut.f_req));
      // Induction strengthening: where the tracked result is.
      if (phase_q == 2'd1) begin
        InP0_A: assert (dut.p0_valid_q && dut.p0_id_q == t_id_q && dut.p0_hit_q == t_hit_q &&
                        dut.p0_skip_q == (t_hit_q && (t_any_q || cfg_mode_i == ModeClosestSpec)) &&
                        dut.p0_node_q == t_node_q &&
                        dut.p0_idx_q == t_idx_q && dut.p0_tag_q == t_tag_q);
      end
      if (phase_q == 2'd2) begin
        InFifo_A: assert (ahead_q < dut.u_fifo.count_q &&
                          dut.u_fifo.mem_q[dut.u_fifo.rd_q + ahead_q[$clog2(FifoDepth)-1:0]] ==
                          {t_id_q, t_action});
      end
      Idle_A: assert (enable_i || !(dut.p0_valid_q || dut.f0_valid_q || skip_valid_o));
      FifoPtr_A: assert (dut.u_fifo.count_q <= CountWidth'(FifoDepth) &&
                         dut.u_fifo.wr_q - dut.u_fifo.rd_q ==
                         dut.u_fifo.count_q[$clog2(FifoDepth)-1:0]);
      // The skip FIFO's registered flags (ab1b8be) follow its count.
      FifoFlags_A: assert (dut.u_fifo.full_q == (dut.u_fifo.count_q == CountWidth'(FifoDepth)) &&
                           dut.u_fifo.empty_q == (dut.u_fifo.count_q == '0));
    end
  end

`ifdef LIVE
  // The downstream is always ready; final outcomes only for rays waiting for one.
  logic [(1 << IdWidth)-1:0] waiting_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) waiting_q <= '0;
    else begin
      if (skip_acc && skip_action_o != ActSkip) waiting_q[skip_id_o] <= 1'b1;
      if (outcome_acc) waiting_q[outcome_id_i] <= 1'b0;
    end
  end
  always_comb begin
    assume (skip_ready_i && tbl_wr_ready_i && tbl_wr2_ready_i);
    if (rst_ni) assume (!outcome_valid_i || waiting_q[outcome_id_i]);
  end
  always_comb begin
    if (rst_ni) begin
      Bounded_A: assert (phase_q == 2'd0 || age_q <= 8'(Bound));
      OutcomeTaken_A: assert (!dut.f0_valid_q || dut.f_advance);
    end
  end
`endif
endmodule

`default_nettype wire
