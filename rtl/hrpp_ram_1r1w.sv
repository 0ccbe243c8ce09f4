`default_nettype none
// Simple dual-port RAM: one synchronous read port, one write port, one clock. Maps to block
// RAM. Read-during-write of one address is the design's business (the pipelines forward), so
// the memory carries no bypass logic (no_rw_check); in simulation such a read returns garbage
// (the inverted old data) so that a design relying on it fails its parity test.
module hrpp_ram_1r1w #(
  parameter int unsigned Depth = 256,  /// number of words
  parameter int unsigned Width = 32,   /// bits per word
  localparam int unsigned AddrWidth = Depth <= 2 ? 1 : $clog2(Depth)
) (
  input  logic                 clk_i,
  input  logic                 re_i,     /// read enable
  input  logic [AddrWidth-1:0] raddr_i,  /// read address
  output logic [Width-1:0]     rdata_o,  /// data of the word read in the previous cycle
  input  logic                 we_i,     /// write enable
  input  logic [AddrWidth-1:0] waddr_i,  /// write address
  input  logic [Width-1:0]     wdata_i   /// write data
);

  // Block RAM also when shallow: a bank of the multi-lane table (rtl/hrpp_lanes.sv) has NumSets /
  // Lanes sets, which Yosys would otherwise put in distributed RAM (the default's 4 lanes: 32
  // sets x 432 bits, about 1,700 DPR16X4 for the eight copies); the pipeline is built around the
  // block RAM's registered read (docs/microarchitecture.md).
  (* no_rw_check, ram_style = "block" *) logic [Width-1:0] mem_q[Depth];

  always_ff @(posedge clk_i) begin
    if (we_i) mem_q[waddr_i] <= wdata_i;
  end

  always_ff @(posedge clk_i) begin
    if (re_i) begin
`ifdef HRPP_SIM_RW_GARBAGE
      rdata_o <= (we_i && waddr_i == raddr_i) ? ~mem_q[raddr_i] : mem_q[raddr_i];
`else
      rdata_o <= mem_q[raddr_i];
`endif
    end
  end

endmodule

`default_nettype wire
