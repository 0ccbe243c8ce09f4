`default_nettype none
// Formal harness of hrpp_hash (docs/verification.md): the pipelined hash equals, for every input
// pattern (six float32 components and the cell exponent), a straightforward combinational
// reference written from docs/hash.md here: one function per field, no pipelining, no shared
// sub-expressions, the fraction test as a mask (the RTL counts trailing zeros), 64-bit
// arithmetic with the clamp (the RTL negates with an incrementer and clamps by its ranges).
module hash_formal
  import hrpp_pkg::*;
#(
  parameter hash_variant_e Variant = HashImproved,
  parameter int unsigned Precision = 6,
  parameter int unsigned ExpBits = 3,
  parameter int unsigned OriginBits = 5,
  parameter int unsigned DirBits = 3,
  parameter combine_e Combine = CombineConcat,
  localparam int unsigned Fo = field_width(Variant, Precision, ExpBits, OriginBits),
  localparam int unsigned Fd = field_width(Variant, Precision, ExpBits, DirBits),
  localparam int unsigned KeyWidth = key_width(Variant, Precision, ExpBits, OriginBits, DirBits,
                                               Combine, DirGrid)
) (
  input logic                  clk_i,
  input logic [2:0][31:0]      org_i,
  input logic [2:0][31:0]      dir_i,
  input logic signed [8:0]     cell_exp_i
);
  logic init_q = 1'b1;
  always_ff @(posedge clk_i) init_q <= 1'b0;
  logic rst_ni;
  assign rst_ni = !init_q;

  logic [KeyWidth-1:0] key_o;
  logic                invalid_o;
  hrpp_hash #(
    .Variant(Variant), .Precision(Precision), .ExpBits(ExpBits), .OriginBits(OriginBits),
    .DirBits(DirBits), .Combine(Combine)
  ) dut (.clk_i, .rst_ni, .org_i, .dir_i, .cell_exp_i, .key_o, .invalid_o);

  // ---------------------------------------------------------------------------------------------
  // The reference (docs/hash.md, steps 1 to 3)
  // ---------------------------------------------------------------------------------------------
  function automatic logic [31:0] ref_canon(logic [31:0] b);
    if (b[30:23] == 8'd0) return 32'd0;                          // +-0, denormals
    if (b[30:23] == 8'd255 && b[22:0] != 23'd0) return 32'h7F80_0000;  // NaN
    return b;
  endfunction

  // Faithful: sign | top ExpBits exponent bits | top Precision mantissa bits.
  function automatic logic [63:0] ref_faithful(logic [31:0] bits);
    logic [31:0] b;
    logic [63:0] s, e, m;
    b = ref_canon(bits);
    s = 64'(b[31]);
    e = ExpBits == 0 ? 64'd0 : 64'(b[30:23]) >> (8 - ExpBits);
    m = 64'(b[22:0]) >> (23 - Precision);
    return (s << (ExpBits + Precision)) | (e << Precision) | m;
  endfunction

  // Improved origin: floor(x / 2^k), its low OriginBits bits in two's complement.
  function automatic logic [63:0] ref_origin(logic [31:0] bits, logic signed [8:0] k);
    logic [31:0] b;
    logic [63:0] mant, mag, v;
    logic        frac;
    int          sh;
    b = ref_canon(bits);
    if (b[30:23] == 8'd255) return b[31] ? 64'd1 << (OriginBits - 1) : (64'd1 << OriginBits) - 1;
    if (b[30:23] == 8'd0) return 64'd0;
    mant = {40'd0, 1'b1, b[22:0]};  // value = mant * 2^(e - 150)
    sh = int'(b[30:23]) - 150 - int'(k);
    frac = 1'b0;
    if (sh >= 0) mag = sh >= 64 ? 64'd0 : mant << sh;
    else if (sh > -64) begin
      mag = mant >> (-sh);
      frac = (mant & ((64'd1 << (-sh)) - 64'd1)) != 64'd0;
    end else begin
      mag = 64'd0;
      frac = 1'b1;
    end
    v = b[31] ? 64'd0 - (mag + 64'(frac)) : mag;
    return v & ((64'd1 << OriginBits) - 1);
  endfunction

  // Improved direction: floor(d * 2^(DirBits-1)), clamped, DirBits bits of two's complement.
  function automatic logic [63:0] ref_dir(logic [31:0] bits);
    logic [31:0]        b;
    logic [63:0]        mant, mag;
    logic               frac;
    logic signed [63:0] q, hi, lo;
    int                 sh;
    b = ref_canon(bits);
    hi = (64'sd1 <<< (DirBits - 1)) - 64'sd1;
    lo = -(64'sd1 <<< (DirBits - 1));
    if (b[30:23] == 8'd0) q = 64'sd0;
    else if (b[30:23] >= 8'd127) q = b[31] ? lo : hi;
    else begin
      mant = {40'd0, 1'b1, b[22:0]};
      sh = 150 - int'(b[30:23]) - int'(DirBits - 1);
      mag = sh >= 64 ? 64'd0 : mant >> sh;
      frac = sh >= 64 ? 1'b1 : (mant & ((64'd1 << sh) - 64'd1)) != 64'd0;
      q = b[31] ? -signed'(mag + 64'(frac)) : signed'(mag);
      if (q > hi) q = hi;
      if (q < lo) q = lo;
    end
    return 64'(q) & ((64'd1 << DirBits) - 1);
  endfunction

  function automatic logic [KeyWidth-1:0] ref_key(logic [2:0][31:0] o, logic [2:0][31:0] d,
                                                  logic signed [8:0] k);
    logic [63:0] ox, oy, oz, dx, dy, dz, ko, kd;
    if (Variant == HashFaithful) begin
      ox = ref_faithful(o[0]);
      oy = ref_faithful(o[1]);
      oz = ref_faithful(o[2]);
      dx = ref_faithful(d[0]);
      dy = ref_faithful(d[1]);
      dz = ref_faithful(d[2]);
    end else begin
      ox = ref_origin(o[0], k);
      oy = ref_origin(o[1], k);
      oz = ref_origin(o[2], k);
      dx = ref_dir(d[0]);
      dy = ref_dir(d[1]);
      dz = ref_dir(d[2]);
    end
    ko = (ox << (2 * Fo)) | (oy << Fo) | oz;  // origin x | y | z
    kd = (dz << (2 * Fd)) | (dy << Fd) | dx;  // direction z | y | x
    if (Combine == CombineXor) return KeyWidth'(ko ^ kd);
    return KeyWidth'((ko << (3 * Fd)) | kd);
  endfunction

  function automatic logic ref_invalid(logic [2:0][31:0] o, logic [2:0][31:0] d);
    return o[0][30:23] == 8'd255 || o[1][30:23] == 8'd255 || o[2][30:23] == 8'd255 ||
           d[0][30:23] == 8'd255 || d[1][30:23] == 8'd255 || d[2][30:23] == 8'd255;
  endfunction

  // The inputs of HashLatency cycles earlier, and whether they were presented after reset.
  logic [HashLatency-1:0][2:0][31:0]  org_q, dir_q;
  logic [HashLatency-1:0][8:0]        k_q;
  logic [HashLatency-1:0]             seen_q;
  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) seen_q <= '0;
    else seen_q <= {seen_q[HashLatency-2:0], 1'b1};
  end
  always_ff @(posedge clk_i) begin
    org_q <= {org_q[HashLatency-2:0], org_i};
    dir_q <= {dir_q[HashLatency-2:0], dir_i};
    k_q   <= {k_q[HashLatency-2:0], cell_exp_i};
  end

  always_comb begin
    if (rst_ni && seen_q[HashLatency-1]) begin
      Key_A: assert (key_o == ref_key(org_q[HashLatency-1], dir_q[HashLatency-1],
                                      signed'(k_q[HashLatency-1])));
      Invalid_A: assert (invalid_o == ref_invalid(org_q[HashLatency-1], dir_q[HashLatency-1]));
    end
  end
endmodule

`default_nettype wire
