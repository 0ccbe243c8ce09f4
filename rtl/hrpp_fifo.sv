`default_nettype none
// Synchronous FIFO with registered storage; the head is visible while not empty. Its full and
// empty flags are registers of their own (set from the count as the count moves), so a handshake
// that waits on them starts at a flip-flop rather than at a compare of the count.
module hrpp_fifo #(
  parameter int unsigned Depth = 8,   /// entries, a power of two
  parameter int unsigned Width = 8,   /// bits per entry
  localparam int unsigned PtrWidth = $clog2(Depth),
  localparam int unsigned CountWidth = $clog2(Depth + 1)
) (
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic              push_i,   /// must not be set when full (asserted)
  input  logic [Width-1:0]  data_i,
  input  logic              pop_i,    /// must not be set when empty (asserted)
  output logic [Width-1:0]  data_o,   /// the head
  output logic              empty_o,
  output logic              full_o,
  output logic [CountWidth-1:0] count_o
);

  logic [Width-1:0]  mem_q[Depth];
  logic [PtrWidth-1:0]   rd_q, wr_q;
  logic [CountWidth-1:0] count_q;
  logic                  full_q, empty_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      rd_q    <= '0;
      wr_q    <= '0;
      count_q <= '0;
      full_q  <= 1'b0;
      empty_q <= 1'b1;
    end else begin
      if (push_i) wr_q <= wr_q + 1'b1;
      if (pop_i) rd_q <= rd_q + 1'b1;
      count_q <= count_q + CountWidth'(push_i) - CountWidth'(pop_i);
      if (push_i && !pop_i) begin
        full_q  <= count_q == CountWidth'(Depth - 1);
        empty_q <= 1'b0;
      end else if (pop_i && !push_i) begin
        full_q  <= 1'b0;
        empty_q <= count_q == CountWidth'(1);
      end
    end
  end

  always_ff @(posedge clk_i) begin
    if (push_i) mem_q[wr_q] <= data_i;
  end

  assign data_o  = mem_q[rd_q];
  assign empty_o = empty_q;
  assign full_o  = full_q;
  assign count_o = count_q;

  // ---------------------------------------------------------------------------------------------
  // Assertions
  // ---------------------------------------------------------------------------------------------
  // The pointers wrap at Depth: it must be a power of two.
  if (Depth < 2 || (Depth & (Depth - 1)) != 0) begin : gen_depth_check
    $error("hrpp_fifo: Depth %0d is not a power of two >= 2", Depth);
  end

`ifndef SYNTHESIS
  NoOverflow_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      push_i |-> !full_o || pop_i);
  NoUnderflow_A: assert property (@(posedge clk_i) disable iff (!rst_ni) pop_i |-> !empty_o);
  FlagsMatchCount_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      full_q == (count_q == CountWidth'(Depth)) && empty_q == (count_q == '0));
`endif

endmodule

`default_nettype wire
