`default_nettype none
// Synthesis flow only (rtl/syn/synth.py): the Fmax ceiling of a table configuration. A bare
// registered block RAM as deep and as wide as one copy of the predictor table's RAM (NumSets
// words of one set row, as hrpp_ram_1r1w is instantiated in hrpp_pred_table): registered
// write enable, addresses and data in, the RAM's synchronous read, registered data out, nothing
// else. Its Fmax is what a design that reads and writes such a RAM every cycle can hope for.
module hrpp_syn_ceiling #(
  parameter int unsigned Depth = 128,  /// words (the table's sets)
  parameter int unsigned Width = 432,  /// bits per word (one set row)
  localparam int unsigned AddrWidth = Depth <= 2 ? 1 : $clog2(Depth)
) (
  input  logic                 clk_i,
  input  logic                 we_i,
  input  logic [AddrWidth-1:0] waddr_i,
  input  logic [AddrWidth-1:0] raddr_i,
  input  logic [Width-1:0]     wdata_i,
  output logic [Width-1:0]     rdata_o
);

  logic                 we_q;
  logic [AddrWidth-1:0] waddr_q, raddr_q;
  logic [Width-1:0]     wdata_q, rdata_q;

  (* no_rw_check *) logic [Width-1:0] mem_q[Depth];

  always_ff @(posedge clk_i) begin
    we_q    <= we_i;
    waddr_q <= waddr_i;
    raddr_q <= raddr_i;
    wdata_q <= wdata_i;
    rdata_o <= rdata_q;
  end

  always_ff @(posedge clk_i) begin
    if (we_q) mem_q[waddr_q] <= wdata_q;
  end

  always_ff @(posedge clk_i) begin
    rdata_q <= mem_q[raddr_q];
  end

endmodule

`default_nettype wire
