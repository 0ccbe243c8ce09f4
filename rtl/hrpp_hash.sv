`default_nettype none
// HRPP hash unit: the key of a ray from the float32 bit patterns of its origin and direction,
// exactly as docs/hash.md specifies (and model/src/hash.cc computes). Combinational; the
// instantiating module registers around it. Rays with an infinite or NaN component are flagged
// invalid_o (they are never looked up or inserted).
module hrpp_hash
  import hrpp_pkg::*;
#(
  parameter hash_variant_e Variant = HashFaithful,  /// faithful (study) or improved (grid)
  parameter int unsigned Precision = 6,    /// faithful: top mantissa bits per component, 1..23
  parameter int unsigned ExpBits = 3,      /// faithful: top exponent bits per component, 0..8
  parameter int unsigned OriginBits = 5,   /// improved: bits per origin axis, 1..16
  parameter int unsigned DirBits = 3,      /// improved: bits per direction component, 1..16
  parameter combine_e Combine = CombineXor,  /// origin and direction fields: XOR or concatenated
  localparam int unsigned FaithW = 1 + ExpBits + Precision,
  localparam int unsigned FieldO = Variant == HashFaithful ? 1 + ExpBits + Precision : OriginBits,
  localparam int unsigned FieldD = Variant == HashFaithful ? 1 + ExpBits + Precision : DirBits,
  localparam int unsigned KeyWidth = Combine == CombineXor ?
      (FieldO > FieldD ? 3 * FieldO : 3 * FieldD) : 3 * FieldO + 3 * FieldD
) (
  input  logic [2:0][31:0]      org_i,       /// origin x, y, z (index 0 = x)
  input  logic [2:0][31:0]      dir_i,       /// direction x, y, z
  input  logic signed [8:0]     cell_exp_i,  /// improved: origin cells are 2^cell_exp_i wide
  output logic [KeyWidth-1:0]   key_o,       /// the key
  output logic                  invalid_o    /// a component is infinite or NaN
);

  // ---------------------------------------------------------------------------------------------
  // Step 1: canonical bit pattern (-0 and denormals to +0, every NaN to +inf)
  // ---------------------------------------------------------------------------------------------
  function automatic logic [31:0] canon(logic [31:0] b);
    if (b[30:23] == 8'd0) return 32'd0;
    if (b[30:23] == 8'hFF && b[22:0] != 23'd0) return 32'h7F80_0000;
    return b;
  endfunction

  // ---------------------------------------------------------------------------------------------
  // Step 2: fields
  // ---------------------------------------------------------------------------------------------
  function automatic logic [FaithW-1:0] faithful_field(logic [31:0] b);
    logic [31:0] c;
    logic [7:0] e_top;  // the top ExpBits exponent bits, right-aligned
    logic [FaithW-1:0] f;
    c = canon(b);
    e_top = c[30:23] >> (8 - ExpBits);
    f = FaithW'(c[31]) << (ExpBits + Precision);
    if (ExpBits > 0) f |= FaithW'(e_top) << Precision;
    f |= FaithW'(c[22:0] >> (23 - Precision));
    return f;
  endfunction

  // floor(x / 2^k), low OriginBits bits, two's complement.
  function automatic logic [OriginBits-1:0] grid_origin_field(logic [31:0] b,
                                                              logic signed [8:0] k);
    logic [31:0] c;
    logic [23:0] mant;
    logic signed [10:0] sh;
    logic [5:0] n;
    logic [OriginBits-1:0] mag;
    logic frac;
    c = canon(b);
    mant = {1'b1, c[22:0]};
    sh = 11'(signed'({3'b0, c[30:23]})) - 11'sd150 - 11'(k);
    mag = '0;
    frac = 1'b0;
    if (c[30:23] == 8'hFF) return c[31] ? OriginBits'(1) << (OriginBits - 1) : '1;
    if (c[30:23] == 8'd0) return '0;
    if (sh >= 0) begin
      if (sh < 11'sd24) mag = OriginBits'({16'd0, mant} << sh[4:0]);  // sh >= 24: low bits zero
      else if (sh < 11'sd40) mag = OriginBits'({mant, 16'd0} << (sh[5:0] - 6'd16));
    end else begin
      n = (sh <= -11'sd24) ? 6'd24 : 6'(-sh);
      mag = OriginBits'(mant >> n);
      frac = (mant & ~(24'hFF_FFFF << n)) != 24'd0 || n == 6'd24;
    end
    return c[31] ? OriginBits'(~(mag + OriginBits'(frac)) + 1'b1) : mag;
  endfunction

  // floor(d * 2^(DirBits-1)) clamped to [-2^(DirBits-1), 2^(DirBits-1)-1], two's complement.
  function automatic logic [DirBits-1:0] grid_dir_field(logic [31:0] b);
    logic [31:0] c;
    logic [23:0] mant;
    logic [7:0] sh;
    logic [DirBits-1:0] mag;
    logic frac;
    c = canon(b);
    mant = {1'b1, c[22:0]};
    if (c[30:23] == 8'd0) return '0;
    if (c[30:23] >= 8'd127)  // |d| >= 1, infinities, NaN: saturate
      return c[31] ? DirBits'(1) << (DirBits - 1) : {1'b0, {(DirBits - 1) {1'b1}}};
    sh = 8'd150 - c[30:23] - 8'(DirBits - 1);  // >= 9: no clamp needed below 1
    mag = sh >= 8'd24 ? '0 : DirBits'(mant >> sh[4:0]);
    frac = sh >= 8'd24 ? 1'b1 : (mant & ~(24'hFF_FFFF << sh[4:0])) != 24'd0;
    return c[31] ? DirBits'(~(mag + DirBits'(frac)) + 1'b1) : mag;
  endfunction

  // ---------------------------------------------------------------------------------------------
  // Step 3: combine (origin x|y|z, direction z|y|x)
  // ---------------------------------------------------------------------------------------------
  logic [3*FieldO-1:0] o_fields;
  logic [3*FieldD-1:0] d_fields;

  always_comb begin
    for (int i = 0; i < 3; i++) begin
      if (Variant == HashFaithful) begin
        o_fields[(2-i)*FieldO +: FieldO] = FieldO'(faithful_field(org_i[i]));
        d_fields[i*FieldD +: FieldD] = FieldD'(faithful_field(dir_i[i]));
      end else begin
        o_fields[(2-i)*FieldO +: FieldO] = FieldO'(grid_origin_field(org_i[i], cell_exp_i));
        d_fields[i*FieldD +: FieldD] = FieldD'(grid_dir_field(dir_i[i]));
      end
    end
  end

  if (Combine == CombineXor) begin : gen_xor
    assign key_o = KeyWidth'(o_fields) ^ KeyWidth'(d_fields);
  end else begin : gen_concat
    assign key_o = {o_fields, d_fields};
  end

  always_comb begin
    invalid_o = 1'b0;
    for (int i = 0; i < 3; i++)
      invalid_o |= org_i[i][30:23] == 8'hFF || dir_i[i][30:23] == 8'hFF;
  end

  // ---------------------------------------------------------------------------------------------
  // Assertions
  // ---------------------------------------------------------------------------------------------
  initial begin : gen_param_checks
    assert (Precision >= 1 && Precision <= 23) else $fatal(1, "Precision must be 1..23");
    assert (ExpBits <= 8) else $fatal(1, "ExpBits must be 0..8");
    assert (OriginBits >= 1 && OriginBits <= 16) else $fatal(1, "OriginBits must be 1..16");
    assert (DirBits >= 1 && DirBits <= 16) else $fatal(1, "DirBits must be 1..16");
    assert (KeyWidth <= 64) else $fatal(1, "keys are at most 64 bits");
  end

endmodule

`default_nettype wire
