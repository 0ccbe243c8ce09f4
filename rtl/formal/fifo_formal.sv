`default_nettype none
// Formal harness of hrpp_fifo (docs/verification.md): an environment that keeps the FIFO's
// contract (no push when full unless popping, no pop when empty), and checks that the count
// follows pushes minus pops, that full and empty agree with it, and that data leaves in order
// (one arbitrary pushed element is tracked to the pop that must return it).
module fifo_formal #(
  parameter int unsigned Depth = 4,
  parameter int unsigned Width = 4
) (
  input logic             clk_i,
  input logic             push_i,
  input logic [Width-1:0] data_i,
  input logic             pop_i,
  input logic             track_i   // choose this cycle's push as the tracked element
);
  localparam int unsigned CountWidth = $clog2(Depth + 1);

  // Reset in the first cycle only.
  logic init_q = 1'b1;
  always_ff @(posedge clk_i) init_q <= 1'b0;
  logic rst_ni;
  assign rst_ni = !init_q;

  logic [Width-1:0]      data_o;
  logic                  empty_o, full_o;
  logic [CountWidth-1:0] count_o;

  hrpp_fifo #(.Depth(Depth), .Width(Width)) dut (
    .clk_i, .rst_ni, .push_i, .data_i, .pop_i, .data_o, .empty_o, .full_o, .count_o
  );

  // The environment keeps the contract.
  always_comb begin
    if (rst_ni) begin
      assume (!push_i || !full_o || pop_i);
      assume (!pop_i || !empty_o);
    end
  end

  // A reference count, one bit wider than the FIFO's.
  logic [CountWidth:0] ref_count_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) ref_count_q <= '0;
    else ref_count_q <= ref_count_q + (CountWidth + 1)'(push_i) - (CountWidth + 1)'(pop_i);
  end

  // The tracked element: its value and how many entries are ahead of it.
  logic                  tracking_q;
  logic [Width-1:0]      tracked_q;
  logic [CountWidth-1:0] ahead_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      tracking_q <= 1'b0;
      tracked_q  <= '0;
      ahead_q    <= '0;
    end else if (!tracking_q) begin
      if (push_i && track_i) begin
        tracking_q <= 1'b1;
        tracked_q  <= data_i;
        ahead_q    <= count_o - CountWidth'(pop_i);
      end
    end else if (pop_i) begin
      if (ahead_q == '0) tracking_q <= 1'b0;
      else ahead_q <= ahead_q - 1'b1;
    end
  end

  always_comb begin
    if (rst_ni) begin
      Count_A: assert (count_o <= CountWidth'(Depth) && {1'b0, count_o} == ref_count_q);
      Empty_A: assert (empty_o == (count_o == '0));
      Full_A: assert (full_o == (count_o == CountWidth'(Depth)));
      // The tracked element is still inside and leaves at its turn with its value.
      TrackedIn_A: assert (!tracking_q || ahead_q < count_o);
      Order_A: assert (!(tracking_q && pop_i && ahead_q == '0) || data_o == tracked_q);
      // Induction strengthening: the pointers and the count agree, the tracked entry sits
      // ahead_q entries behind the read pointer.
      Ptr_A: assert (dut.wr_q - dut.rd_q == dut.count_q[$clog2(Depth)-1:0]);
      Mem_A: assert (!tracking_q || dut.mem_q[dut.rd_q + ahead_q[$clog2(Depth)-1:0]] == tracked_q);
    end
  end
endmodule

`default_nettype wire
