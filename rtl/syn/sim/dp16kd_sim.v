// ECP5 DP16KD block RAM, for simulating the ECP5 netlists of rtl/syn/synth.py (`make
// synth-check`). Yosys ships the cell as a black box (share/ecp5/cells_sim.v); this model is
// written from the port semantics Yosys's own mapping assumes (share/lattice/brams_16kd.txt,
// brams_map_16kd.v), not from the vendor's model. It covers what that mapping and the flow's
// output-register move (rtl/syn/outreg.py) produce, and stops the simulation on anything else:
//
//   * true dual port, both ports one width of 1, 2, 4, 9 or 18 bits (the word address is
//     AD[13:k], k = 0, 1, 2, 3, 4; at 18 bits AD[1:0] are the write's two 9-bit byte enables,
//     below 18 bits WE alone writes), or pseudo dual port at 36 bits (Yosys's $__PDPW16KD_:
//     port A writes {DIB, DIA} at AD[13:5] with ADA[3:0] as its four 9-bit byte enables, port B
//     reads it onto {DOB, DOA}, under port B's clock enable, output register and reset);
//   * CE: the port's clock enable (reads and writes); WRITEMODE of a port that reads and writes
//     one word in a cycle: NORMAL keeps its output, WRITETHROUGH shows the new word,
//     READBEFOREWRITE the old one;
//   * REGMODE NOREG: the output is the port's read latch; OUTREG: a register behind the latch,
//     loaded from it on the clock when OCE is high (so the word read in cycle t appears after
//     the clock of cycle t+1);
//   * RST, active high, clears the output register (OUTREG) or the read latch (NOREG):
//     RESETMODE SYNC on the clock, not gated by CE or OCE; ASYNC with ASYNC_RESET_RELEASE ASYNC
//     at once, like an asynchronously reset flip-flop;
//   * CSDECODE "0b000" with the chip selects tied low, CLKxMUX not inverted, INITVAL zero (the
//     designs clear their tables).
//
// A word read from one port while the other writes it in the same cycle reads as the inverted
// old word (hrpp_ram_1r1w's HRPP_SIM_RW_GARBAGE), so that a design relying on it fails.
`default_nettype none
/* verilator lint_off MULTIDRIVEN */
/* verilator lint_off UNUSEDPARAM */
/* verilator lint_off UNUSEDSIGNAL */
module DP16KD (
  input wire DIA17, DIA16, DIA15, DIA14, DIA13, DIA12, DIA11, DIA10, DIA9, DIA8, DIA7, DIA6,
  input wire DIA5, DIA4, DIA3, DIA2, DIA1, DIA0,
  input wire ADA13, ADA12, ADA11, ADA10, ADA9, ADA8, ADA7, ADA6, ADA5, ADA4, ADA3, ADA2, ADA1,
  input wire ADA0,
  input wire CEA, OCEA, CLKA, WEA, RSTA,
  input wire CSA2, CSA1, CSA0,
  output wire DOA17, DOA16, DOA15, DOA14, DOA13, DOA12, DOA11, DOA10, DOA9, DOA8, DOA7, DOA6,
  output wire DOA5, DOA4, DOA3, DOA2, DOA1, DOA0,
  input wire DIB17, DIB16, DIB15, DIB14, DIB13, DIB12, DIB11, DIB10, DIB9, DIB8, DIB7, DIB6,
  input wire DIB5, DIB4, DIB3, DIB2, DIB1, DIB0,
  input wire ADB13, ADB12, ADB11, ADB10, ADB9, ADB8, ADB7, ADB6, ADB5, ADB4, ADB3, ADB2, ADB1,
  input wire ADB0,
  input wire CEB, OCEB, CLKB, WEB, RSTB,
  input wire CSB2, CSB1, CSB0,
  output wire DOB17, DOB16, DOB15, DOB14, DOB13, DOB12, DOB11, DOB10, DOB9, DOB8, DOB7, DOB6,
  output wire DOB5, DOB4, DOB3, DOB2, DOB1, DOB0
);
  parameter integer DATA_WIDTH_A = 18;
  parameter integer DATA_WIDTH_B = 18;
  parameter REGMODE_A = "NOREG";
  parameter REGMODE_B = "NOREG";
  parameter RESETMODE = "SYNC";
  parameter ASYNC_RESET_RELEASE = "SYNC";
  parameter CSDECODE_A = "0b000";
  parameter CSDECODE_B = "0b000";
  parameter WRITEMODE_A = "NORMAL";
  parameter WRITEMODE_B = "NORMAL";
  parameter CLKAMUX = "CLKA";
  parameter CLKBMUX = "CLKB";
  parameter GSR = "ENABLED";
  parameter INIT_DATA = "STATIC";
  parameter WID = 0;
  parameter [319:0] INITVAL_00 = 320'h0;
  parameter [319:0] INITVAL_01 = 320'h0;
  parameter [319:0] INITVAL_02 = 320'h0;
  parameter [319:0] INITVAL_03 = 320'h0;
  parameter [319:0] INITVAL_04 = 320'h0;
  parameter [319:0] INITVAL_05 = 320'h0;
  parameter [319:0] INITVAL_06 = 320'h0;
  parameter [319:0] INITVAL_07 = 320'h0;
  parameter [319:0] INITVAL_08 = 320'h0;
  parameter [319:0] INITVAL_09 = 320'h0;
  parameter [319:0] INITVAL_0A = 320'h0;
  parameter [319:0] INITVAL_0B = 320'h0;
  parameter [319:0] INITVAL_0C = 320'h0;
  parameter [319:0] INITVAL_0D = 320'h0;
  parameter [319:0] INITVAL_0E = 320'h0;
  parameter [319:0] INITVAL_0F = 320'h0;
  parameter [319:0] INITVAL_10 = 320'h0;
  parameter [319:0] INITVAL_11 = 320'h0;
  parameter [319:0] INITVAL_12 = 320'h0;
  parameter [319:0] INITVAL_13 = 320'h0;
  parameter [319:0] INITVAL_14 = 320'h0;
  parameter [319:0] INITVAL_15 = 320'h0;
  parameter [319:0] INITVAL_16 = 320'h0;
  parameter [319:0] INITVAL_17 = 320'h0;
  parameter [319:0] INITVAL_18 = 320'h0;
  parameter [319:0] INITVAL_19 = 320'h0;
  parameter [319:0] INITVAL_1A = 320'h0;
  parameter [319:0] INITVAL_1B = 320'h0;
  parameter [319:0] INITVAL_1C = 320'h0;
  parameter [319:0] INITVAL_1D = 320'h0;
  parameter [319:0] INITVAL_1E = 320'h0;
  parameter [319:0] INITVAL_1F = 320'h0;
  parameter [319:0] INITVAL_20 = 320'h0;
  parameter [319:0] INITVAL_21 = 320'h0;
  parameter [319:0] INITVAL_22 = 320'h0;
  parameter [319:0] INITVAL_23 = 320'h0;
  parameter [319:0] INITVAL_24 = 320'h0;
  parameter [319:0] INITVAL_25 = 320'h0;
  parameter [319:0] INITVAL_26 = 320'h0;
  parameter [319:0] INITVAL_27 = 320'h0;
  parameter [319:0] INITVAL_28 = 320'h0;
  parameter [319:0] INITVAL_29 = 320'h0;
  parameter [319:0] INITVAL_2A = 320'h0;
  parameter [319:0] INITVAL_2B = 320'h0;
  parameter [319:0] INITVAL_2C = 320'h0;
  parameter [319:0] INITVAL_2D = 320'h0;
  parameter [319:0] INITVAL_2E = 320'h0;
  parameter [319:0] INITVAL_2F = 320'h0;
  parameter [319:0] INITVAL_30 = 320'h0;
  parameter [319:0] INITVAL_31 = 320'h0;
  parameter [319:0] INITVAL_32 = 320'h0;
  parameter [319:0] INITVAL_33 = 320'h0;
  parameter [319:0] INITVAL_34 = 320'h0;
  parameter [319:0] INITVAL_35 = 320'h0;
  parameter [319:0] INITVAL_36 = 320'h0;
  parameter [319:0] INITVAL_37 = 320'h0;
  parameter [319:0] INITVAL_38 = 320'h0;
  parameter [319:0] INITVAL_39 = 320'h0;
  parameter [319:0] INITVAL_3A = 320'h0;
  parameter [319:0] INITVAL_3B = 320'h0;
  parameter [319:0] INITVAL_3C = 320'h0;
  parameter [319:0] INITVAL_3D = 320'h0;
  parameter [319:0] INITVAL_3E = 320'h0;
  parameter [319:0] INITVAL_3F = 320'h0;

  localparam integer PDP = DATA_WIDTH_A == 36;                 // pseudo dual port, 36 bits
  localparam integer W = PDP ? 36 : DATA_WIDTH_A;              // word width
  localparam integer K = W == 36 ? 5 : W == 18 ? 4 : W == 9 ? 3 : W == 4 ? 2 : W == 2 ? 1 : 0;
  localparam integer WORDS = 16384 >> K;
  localparam integer OUTREG_A = REGMODE_A == "OUTREG";
  localparam integer OUTREG_B = REGMODE_B == "OUTREG";
  localparam integer ASYNC = RESETMODE == "ASYNC";

  initial begin
    if (!(DATA_WIDTH_A == DATA_WIDTH_B &&
          (W == 1 || W == 2 || W == 4 || W == 9 || W == 18 || W == 36)))
      $fatal(1, "DP16KD model: port widths %0d / %0d not modelled", DATA_WIDTH_A, DATA_WIDTH_B);
    if (PDP && REGMODE_A != REGMODE_B)
      $fatal(1, "DP16KD model: 36-bit mode with REGMODE_A %s and REGMODE_B %s", REGMODE_A,
             REGMODE_B);
    if (!(REGMODE_A == "NOREG" || REGMODE_A == "OUTREG") ||
        !(REGMODE_B == "NOREG" || REGMODE_B == "OUTREG"))
      $fatal(1, "DP16KD model: REGMODE %s / %s not modelled", REGMODE_A, REGMODE_B);
    if (!(RESETMODE == "SYNC" || (RESETMODE == "ASYNC" && ASYNC_RESET_RELEASE == "ASYNC")))
      $fatal(1, "DP16KD model: RESETMODE %s with ASYNC_RESET_RELEASE %s not modelled",
             RESETMODE, ASYNC_RESET_RELEASE);
    if (CSDECODE_A != "0b000" || CSDECODE_B != "0b000" || CLKAMUX != "CLKA" ||
        CLKBMUX != "CLKB")
      $fatal(1, "DP16KD model: chip-select decode or inverted clock not modelled");
    if (|{INITVAL_00, INITVAL_01, INITVAL_02, INITVAL_03, INITVAL_04, INITVAL_05, INITVAL_06,
          INITVAL_07, INITVAL_08, INITVAL_09, INITVAL_0A, INITVAL_0B, INITVAL_0C, INITVAL_0D,
          INITVAL_0E, INITVAL_0F, INITVAL_10, INITVAL_11, INITVAL_12, INITVAL_13, INITVAL_14,
          INITVAL_15, INITVAL_16, INITVAL_17, INITVAL_18, INITVAL_19, INITVAL_1A, INITVAL_1B,
          INITVAL_1C, INITVAL_1D, INITVAL_1E, INITVAL_1F, INITVAL_20, INITVAL_21, INITVAL_22,
          INITVAL_23, INITVAL_24, INITVAL_25, INITVAL_26, INITVAL_27, INITVAL_28, INITVAL_29,
          INITVAL_2A, INITVAL_2B, INITVAL_2C, INITVAL_2D, INITVAL_2E, INITVAL_2F, INITVAL_30,
          INITVAL_31, INITVAL_32, INITVAL_33, INITVAL_34, INITVAL_35, INITVAL_36, INITVAL_37,
          INITVAL_38, INITVAL_39, INITVAL_3A, INITVAL_3B, INITVAL_3C, INITVAL_3D, INITVAL_3E,
          INITVAL_3F})
      $fatal(1, "DP16KD model: initial contents (INITVAL_*) not modelled");
  end

  wire [17:0] dia = {DIA17, DIA16, DIA15, DIA14, DIA13, DIA12, DIA11, DIA10, DIA9, DIA8, DIA7,
                     DIA6, DIA5, DIA4, DIA3, DIA2, DIA1, DIA0};
  wire [17:0] dib = {DIB17, DIB16, DIB15, DIB14, DIB13, DIB12, DIB11, DIB10, DIB9, DIB8, DIB7,
                     DIB6, DIB5, DIB4, DIB3, DIB2, DIB1, DIB0};
  wire [13:0] ada = {ADA13, ADA12, ADA11, ADA10, ADA9, ADA8, ADA7, ADA6, ADA5, ADA4, ADA3, ADA2,
                     ADA1, ADA0};
  wire [13:0] adb = {ADB13, ADB12, ADB11, ADB10, ADB9, ADB8, ADB7, ADB6, ADB5, ADB4, ADB3, ADB2,
                     ADB1, ADB0};
  wire [13:0] wa = ada >> K, wb = adb >> K;  // word addresses
  wire cs_a = !CSA2 && !CSA1 && !CSA0, cs_b = !CSB2 && !CSB1 && !CSB0;

  // Per 9-bit byte, whether a port's write writes it (bits 0..3 of the 36-bit word).
  wire [3:0] be_a = PDP ? ada[3:0] : W == 18 ? {2'b00, ada[1:0]} : 4'b0001;
  wire [3:0] be_b = W == 18 ? {2'b00, adb[1:0]} : 4'b0001;
  wire wr_a = CEA && cs_a && WEA && |be_a;
  wire wr_b = !PDP && CEB && cs_b && WEB && |be_b;
  wire rd_a = !PDP && CEA && cs_a;
  wire rd_b = CEB && cs_b;

  wire [35:0] wd_a = PDP ? {dib, dia} : {18'b0, dia};
  wire [35:0] wd_b = {18'b0, dib};
  function [35:0] merge(input [35:0] old, input [35:0] d, input [3:0] be);
    integer i;
    begin
      merge = old;
      if (W >= 18) begin
        for (i = 0; i < 4; i = i + 1) if (be[i]) merge[9 * i +: 9] = d[9 * i +: 9];
      end else begin
        merge = d & ((36'd1 << W) - 36'd1);
      end
    end
  endfunction

  reg [35:0] mem[0:WORDS-1];
  reg [35:0] lat_a, lat_b;  // the read latches
  reg [35:0] out_a, out_b;  // the output registers (OUTREG)

  // Port A: writes (both modes) and reads (true dual port)
  always @(posedge CLKA) begin
    if (wr_a) mem[wa] <= merge(mem[wa], wd_a, be_a);
  end
  always @(posedge CLKB) begin
    if (wr_b) mem[wb] <= merge(mem[wb], wd_b, be_b);
  end

  // The word a port reads in this cycle, with the write-mode and collision rules above.
  wire [35:0] rd_word_a =
      wr_a ? (WRITEMODE_A == "WRITETHROUGH" ? merge(mem[wa], wd_a, be_a) : mem[wa]) :
      (wr_b && wb == wa) ? ~mem[wa] : mem[wa];
  wire [35:0] rd_word_b =
      wr_b ? (WRITEMODE_B == "WRITETHROUGH" ? merge(mem[wb], wd_b, be_b) : mem[wb]) :
      (wr_a && wa == wb) ? ~mem[wb] : mem[wb];
  wire keep_a = wr_a && WRITEMODE_A == "NORMAL";
  wire keep_b = wr_b && WRITEMODE_B == "NORMAL";

  generate
    if (ASYNC) begin : g_async
      always @(posedge CLKA or posedge RSTA) begin
        if (RSTA) begin
          if (OUTREG_A) out_a <= 36'b0; else lat_a <= 36'b0;
        end else begin
          if (rd_a && !keep_a) lat_a <= rd_word_a;
          if (OUTREG_A && OCEA) out_a <= lat_a;
        end
      end
      always @(posedge CLKB or posedge RSTB) begin
        if (RSTB) begin
          if (OUTREG_B) out_b <= 36'b0; else lat_b <= 36'b0;
        end else begin
          if (rd_b && !keep_b) lat_b <= rd_word_b;
          if (OUTREG_B && OCEB) out_b <= lat_b;
        end
      end
    end else begin : g_sync
      always @(posedge CLKA) begin
        if (rd_a && !keep_a) lat_a <= rd_word_a;
        if (OUTREG_A && OCEA) out_a <= lat_a;
        if (RSTA) begin
          if (OUTREG_A) out_a <= 36'b0; else lat_a <= 36'b0;
        end
      end
      always @(posedge CLKB) begin
        if (rd_b && !keep_b) lat_b <= rd_word_b;
        if (OUTREG_B && OCEB) out_b <= lat_b;
        if (RSTB) begin
          if (OUTREG_B) out_b <= 36'b0; else lat_b <= 36'b0;
        end
      end
    end
  endgenerate

  // The outputs: in 36-bit mode port B's word on {DOB, DOA}.
  wire [35:0] q_a = OUTREG_A ? out_a : lat_a;
  wire [35:0] q_b = OUTREG_B ? out_b : lat_b;
  wire [17:0] doa = PDP ? q_b[17:0] : q_a[17:0];
  wire [17:0] dob = PDP ? q_b[35:18] : q_b[17:0];
  assign {DOA17, DOA16, DOA15, DOA14, DOA13, DOA12, DOA11, DOA10, DOA9, DOA8, DOA7, DOA6, DOA5,
          DOA4, DOA3, DOA2, DOA1, DOA0} = doa;
  assign {DOB17, DOB16, DOB15, DOB14, DOB13, DOB12, DOB11, DOB10, DOB9, DOB8, DOB7, DOB6, DOB5,
          DOB4, DOB3, DOB2, DOB1, DOB0} = dob;
endmodule
`default_nettype wire
