`default_nettype none
// HRPP hash unit: the key of a ray from the float32 bit patterns of its origin and direction,
// exactly as docs/hash.md specifies (and model/src/predictor/hash.cc computes). Pipelined: key_o and
// invalid_o belong to the inputs of HashLatency (hrpp_pkg: 3) cycles earlier.
//   stage 1 : canonicalize; shift amounts and trailing-zero counts of the significands
//   stage 1b: shift direction, saturated shift amount
//   stage 2 : shifts (the sticky bit is "trailing zeros < shift"), magnitudes
//   output : two's-complement negation, origin/direction combination (combinational)
// The octahedral direction code (DirCode = DirOct, improved variant) runs beside the origin
// fields in the same three stages (gen_oct below).
// Rays with an infinite or NaN component are flagged invalid_o (never looked up or inserted).
module hrpp_hash
  import hrpp_pkg::*;
#(
  parameter hash_variant_e Variant = HashFaithful,  /// faithful (study) or improved (grid)
  parameter int unsigned Precision = 6,    /// faithful: top mantissa bits per component, 1..23
  parameter int unsigned ExpBits = 3,      /// faithful: top exponent bits per component, 0..8
  parameter int unsigned OriginBits = 5,   /// improved: bits per origin axis, 1..16
  parameter int unsigned DirBits = 3,      /// improved: bits per direction component, 1..16
  parameter combine_e Combine = CombineXor,  /// origin and direction fields: XOR or concatenated
  parameter dir_code_e DirCode = DirGrid,  /// improved: direction grid or octahedral (DirBits 1..8)
  localparam int unsigned FaithWidth = 1 + ExpBits + Precision,
  localparam int unsigned OriginFieldWidth = field_width(Variant, Precision, ExpBits, OriginBits),
  localparam int unsigned DirFieldWidth = field_width(Variant, Precision, ExpBits, DirBits),
  localparam int unsigned KeyWidth = key_width(Variant, Precision, ExpBits, OriginBits, DirBits,
                                               Combine, DirCode),
  localparam int unsigned MaxFieldWidth = FaithWidth > 16 ? FaithWidth : 16  // widest field
) (
  input  logic                  clk_i,
  input  logic                  rst_ni,
  input  logic [2:0][31:0]      org_i,       /// origin x, y, z (index 0 = x)
  input  logic [2:0][31:0]      dir_i,       /// direction x, y, z
  input  logic signed [8:0]     cell_exp_i,  /// improved: origin cells are 2^cell_exp_i wide
  output logic [KeyWidth-1:0]   key_o,       /// the key (HashLatency cycles later)
  output logic                  invalid_o    /// a component was infinite or NaN
);

  // Canonical bit pattern (-0 and denormals to +0, every NaN to +inf).
  function automatic logic [31:0] canon(logic [31:0] b);
    if (b[30:23] == 8'd0) return 32'd0;
    if (b[30:23] == 8'hFF && b[22:0] != 23'd0) return 32'h7F80_0000;
    return b;
  endfunction

  // Faithful field: sign | top ExpBits exponent bits | top Precision mantissa bits.
  function automatic logic [FaithWidth-1:0] faithful_field(logic [31:0] c);
    logic [7:0] e_top;  // the top ExpBits exponent bits, right-aligned
    logic [FaithWidth-1:0] f;
    e_top = c[30:23] >> (8 - ExpBits);
    f = FaithWidth'(c[31]) << (ExpBits + Precision);
    if (ExpBits > 0) f |= FaithWidth'(e_top) << Precision;
    f |= FaithWidth'(c[22:0] >> (23 - Precision));
    return f;
  endfunction

  // Trailing zeros of a nonzero 24-bit significand (its bit 23 is set): 0..23.
  function automatic logic [4:0] trailing_zeros(logic [23:0] m);
    logic [4:0] n;
    n = 5'd23;
    for (int i = 22; i >= 0; i--)
      if (m[i]) n = 5'(i);
    return n;
  endfunction

  // ---------------------------------------------------------------------------------------------
  // Stage 1
  // ---------------------------------------------------------------------------------------------
  // Per component (0..2 origin x, y, z; 3..5 direction x, y, z):
  typedef struct packed {
    logic            fixed;  // the field is known: `field` (faithful; zero; special; saturated)
    logic [MaxFieldWidth-1:0] field;
    logic            sign;
    logic [23:0]     mant;
    logic [4:0]      tz;     // trailing zeros of mant
    logic signed [10:0] sh;  // origin: e - 150 - k (a left shift if >= 0); direction: right shift
    logic signed [10:0] rsh; // the right shift: origin 150 + k - e (= -sh); direction sh
  } s1_t;

  s1_t [5:0] s1_d, s1_q;
  logic      inv1_d, inv1_q;

  always_comb begin
    inv1_d = 1'b0;
    for (int i = 0; i < 6; i++) begin
      logic [31:0] b, c;
      b = i < 3 ? org_i[i] : dir_i[i-3];
      c = canon(b);
      inv1_d |= b[30:23] == 8'hFF;
      s1_d[i] = '0;
      // Sign, significand, trailing zeros and shift come from the raw pattern, in parallel with
      // the canonicalization: they matter only for a component that is not `fixed`, and every
      // pattern canon() changes (zero, denormal, NaN) is fixed.
      s1_d[i].sign = b[31];
      s1_d[i].mant = {1'b1, b[22:0]};
      s1_d[i].tz = trailing_zeros({1'b1, b[22:0]});
      if (Variant == HashFaithful) begin
        s1_d[i].fixed = 1'b1;
        s1_d[i].field = MaxFieldWidth'(faithful_field(c));
      end else if (c[30:23] == 8'd0) begin
        s1_d[i].fixed = 1'b1;  // field 0
      end else if (i < 3) begin
        if (c[30:23] == 8'hFF) begin  // +inf and NaN: all ones; -inf: 1 then zeros
          s1_d[i].fixed = 1'b1;
          s1_d[i].field = c[31] ? MaxFieldWidth'(1) << (OriginBits - 1)
                                : MaxFieldWidth'((1 << OriginBits) - 1);
        end
        s1_d[i].sh = 11'(signed'({3'b0, b[30:23]})) - 11'sd150 - 11'(cell_exp_i);
        s1_d[i].rsh = 11'sd150 + 11'(cell_exp_i) - 11'(signed'({3'b0, b[30:23]}));
      end else begin
        if (c[30:23] >= 8'd127) begin  // |d| >= 1, infinities, NaN: saturate
          s1_d[i].fixed = 1'b1;
          s1_d[i].field = c[31] ? MaxFieldWidth'(1) << (DirBits - 1)
                                : MaxFieldWidth'((1 << (DirBits - 1)) - 1);
        end
        // Right shift of the significand for floor(d * 2^(DirBits-1)); >= 9 since e <= 126.
        s1_d[i].sh = 11'sd150 - 11'(signed'({3'b0, b[30:23]})) - 11'(DirBits - 1);
        s1_d[i].rsh = s1_d[i].sh;
      end
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Stage 2: magnitudes
  // ---------------------------------------------------------------------------------------------
  typedef struct packed {
    logic            fixed;
    logic [MaxFieldWidth-1:0] field;
    logic            neg;   // negate (mag + frac)
    logic [15:0]     mag;   // the low field bits of |x| shifted (truncated)
    logic            frac;  // bits were shifted out (floor of a negative value subtracts one)
  } s2_t;

  s2_t [5:0] s2_d, s2_q;
  logic      inv2_q;

  // Stage 1b: the shift of each component (direction and saturated amount), registered so that
  // stage 2 is only the shifter and the sticky compare.
  typedef struct packed {
    logic            fixed;
    logic [MaxFieldWidth-1:0] field;
    logic            sign;
    logic [23:0]     mant;
    logic [4:0]      tz;
    logic            left;  // origin with sh >= 0: left shift by lsh (zero if lsh >= 16)
    logic            lok;   // sh < 16
    logic [3:0]      lsh;
    logic [5:0]      n;     // right shift, saturated at 24
  } s1b_t;

  s1b_t [5:0] s1b_d, s1b_q;
  logic       inv1b_q;

  always_comb begin
    for (int i = 0; i < 6; i++) begin
      s1b_d[i] = '0;
      s1b_d[i].fixed = s1_q[i].fixed;
      s1b_d[i].field = s1_q[i].field;
      s1b_d[i].sign  = s1_q[i].sign;
      s1b_d[i].mant  = s1_q[i].mant;
      s1b_d[i].tz    = s1_q[i].tz;
      s1b_d[i].left  = i < 3 && s1_q[i].sh >= 0;
      s1b_d[i].lok   = s1_q[i].sh < 11'sd16;
      s1b_d[i].lsh   = s1_q[i].sh[3:0];
      s1b_d[i].n     = (s1_q[i].rsh >= 11'sd24) ? 6'd24 : 6'(s1_q[i].rsh);
    end
  end

  always_comb begin
    for (int i = 0; i < 6; i++) begin
      s2_d[i] = '0;
      s2_d[i].fixed = s1b_q[i].fixed;
      s2_d[i].field = s1b_q[i].field;
      s2_d[i].neg = s1b_q[i].sign;
      if (s1b_q[i].left) begin  // |x| / 2^k is an integer: left shift
        if (s1b_q[i].lok) s2_d[i].mag = 16'(s1b_q[i].mant << s1b_q[i].lsh);
      end else begin            // right shift by n, fraction bits shifted out
        s2_d[i].mag = 16'(s1b_q[i].mant >> s1b_q[i].n);
        s2_d[i].frac = {1'b0, s1b_q[i].tz} < s1b_q[i].n;
      end
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      s1_q    <= '0;
      inv1_q  <= 1'b0;
      s1b_q   <= '0;
      inv1b_q <= 1'b0;
      s2_q    <= '0;
      inv2_q  <= 1'b0;
    end else begin
      s1_q    <= s1_d;
      inv1_q  <= inv1_d;
      s1b_q   <= s1b_d;
      inv1b_q <= inv1_q;
      s2_q    <= s2_d;
      inv2_q  <= inv1b_q;
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Output: fields, combination (origin x|y|z, direction z|y|x)
  // ---------------------------------------------------------------------------------------------
  logic [5:0][MaxFieldWidth-1:0] field;
  if (Variant == HashFaithful) begin : gen_field_faithful
    // A faithful field is always `fixed` (its register is 0 only after reset, when the field is 0
    // too): the key takes the field register as it is, and synthesis removes the magnitude path
    // (its incrementers), which would otherwise end in the key.
    always_comb begin
      for (int i = 0; i < 6; i++) field[i] = s2_q[i].field;
    end
    logic magnitude_unused;  // the magnitude path: not used by the faithful hash
    assign magnitude_unused = ^s2_q;
  end else begin : gen_field_improved
    always_comb begin
      for (int i = 0; i < 6; i++) begin
        if (s2_q[i].fixed) field[i] = s2_q[i].field;
        // -(mag + frac) = ~mag + 1 - frac: one incrementer instead of an adder and a negation.
        else if (s2_q[i].neg) field[i] = MaxFieldWidth'(16'(~s2_q[i].mag + 16'(!s2_q[i].frac)));
        else field[i] = MaxFieldWidth'(s2_q[i].mag);
      end
    end
  end

  logic [3*OriginFieldWidth-1:0] o_fields;
  logic [3*DirFieldWidth-1:0] d_fields;
  always_comb begin
    for (int i = 0; i < 3; i++) begin
      o_fields[(2-i)*OriginFieldWidth +: OriginFieldWidth] = OriginFieldWidth'(field[i]);
      d_fields[i*DirFieldWidth +: DirFieldWidth] = DirFieldWidth'(field[3+i]);
    end
  end

  // The direction's part of the key: the grid fields z | y | x, or the octahedral field u | v.
  localparam bit OctDir = Variant == HashImproved && DirCode == DirOct;
  localparam int unsigned DKeyWidth = OctDir ? 2 * DirBits : 3 * DirFieldWidth;
  logic [DKeyWidth-1:0] d_key;

  if (OctDir) begin : gen_oct
    // -------------------------------------------------------------------------------------------
    // Octahedral direction code (docs/hash.md, "Octahedral direction code"), b = DirBits,
    // h = 2^(b-1): beside the origin fields, in the same stages.
    //   stage 1 : pairwise exponent differences, shift E - e_i (saturated at 24), significands,
    //             signs (canonical)
    //   stage 1b: aligned magnitudes A_i = sig_i >> (E - e_i)
    //   stage 2 : L = A_x + A_y + A_z (carry-save, then one adder), the folded numerators Nu, Nv,
    //             the multiples j * L (j = 2..h-1) from L's carry-save form
    //   output  : compares N * h >= j * L, bins (the count of true compares), fields u | v
    // The grid direction fields above are not used (synthesis removes them).
    // -------------------------------------------------------------------------------------------
    localparam int unsigned Half = 1 << (DirBits - 1);  // h
    localparam int unsigned NumMult = Half > 1 ? Half - 1 : 1;  // multiples j = 1..h-1 (>= 1 slot)
    localparam int unsigned LW = 26;                    // L < 3 * 2^24
    localparam int unsigned MW = LW + DirBits;          // j * L < 2^(b-1) * 2^26; N * h < 2^(24+b)

    logic [2:0]       s1o_sign_d, s1o_sign_q;   // canonical signs
    logic [2:0][23:0] s1o_sig_d, s1o_sig_q;     // canonical significands (0 for a zero)
    logic [2:0][4:0]  s1o_sh_d, s1o_sh_q;       // E - e_i, saturated at 24

    always_comb begin
      logic [2:0][7:0] e;
      logic [2:0][2:0][8:0] diff;  // diff[i][k] = e_k - e_i (9 bits, two's complement)
      logic ge_xy, ge_xz, ge_yz, max_x, max_y;
      logic [2:0][8:0] d;
      for (int i = 0; i < 3; i++) begin
        logic [31:0] b;
        b = dir_i[i];
        e[i] = b[30:23];  // the canonical exponent equals the raw one (zero stays 0, NaN 255)
        s1o_sig_d[i] = b[30:23] == 8'd0 ? 24'd0
                     : {1'b1, b[30:23] == 8'hFF ? 23'd0 : b[22:0]};  // NaN is +inf
        s1o_sign_d[i] = b[31] && b[30:23] != 8'd0 && !(b[30:23] == 8'hFF && b[22:0] != 23'd0);
      end
      for (int i = 0; i < 3; i++)
        for (int k = 0; k < 3; k++) diff[i][k] = {1'b0, e[k]} - {1'b0, e[i]};
      // Which exponent is the largest (the first of equal ones): the signs of the differences.
      ge_xy = !diff[1][0][8];  // e_x - e_y >= 0
      ge_xz = !diff[2][0][8];
      ge_yz = !diff[2][1][8];
      max_x = ge_xy && ge_xz;
      max_y = !max_x && ge_yz;
      d[0] = max_x ? 9'd0 : max_y ? diff[0][1] : diff[0][2];
      d[1] = max_y ? 9'd0 : max_x ? diff[1][0] : diff[1][2];
      d[2] = (max_x || max_y) ? (max_x ? diff[2][0] : diff[2][1]) : 9'd0;
      for (int i = 0; i < 3; i++) s1o_sh_d[i] = d[i] >= 9'd24 ? 5'd24 : d[i][4:0];
    end

    logic [2:0]       s1bo_sign_q;
    logic [2:0][23:0] s1bo_a_d, s1bo_a_q;  // A_i
    always_comb begin
      for (int i = 0; i < 3; i++) s1bo_a_d[i] = s1o_sig_q[i] >> s1o_sh_q[i];
    end

    logic [1:0]              s2o_sign_q;           // s_x, s_y
    logic [LW-2:0]           s2o_nu_d, s2o_nu_q;   // Nu, Nv (25 bits)
    logic [LW-2:0]           s2o_nv_d, s2o_nv_q;
    logic [NumMult:1][MW-1:0] s2o_mult_d, s2o_mult_q;  // j * L
    always_comb begin
      logic [LW-1:0] ls, lc, l;  // L in carry-save form (ls + lc), and L
      logic [2:0][LW-1:0] a;
      logic [MW-1:0] s, c, x;    // a multiple in carry-save form (s + c); x the next addend
      for (int i = 0; i < 3; i++) a[i] = LW'(s1bo_a_q[i]);
      ls = a[0] ^ a[1] ^ a[2];
      lc = ((a[0] & a[1]) | (a[0] & a[2]) | (a[1] & a[2])) << 1;
      l = ls + lc;
      // Upper hemisphere (s_z = 0): (A_x, A_y); lower: the fold (A_x + A_z, A_y + A_z).
      s2o_nu_d = (LW - 1)'(a[0]) + (s1bo_sign_q[2] ? (LW - 1)'(a[2]) : '0);
      s2o_nv_d = (LW - 1)'(a[1]) + (s1bo_sign_q[2] ? (LW - 1)'(a[2]) : '0);
      s2o_mult_d = '0;
      for (int j = 1; j <= NumMult; j++) begin
        s = '0;
        c = '0;
        x = '0;
        if ((j & (j - 1)) == 0) begin  // a power of two: a shift of L
          for (int k = 0; k < 8; k++)
            if (j == (1 << k)) s = MW'(l) << k;
        end else begin  // the shifted copies of ls and lc added in carry-save form
          for (int k = 0; k < 8; k++)
            if (((j >> k) & 1) != 0) begin
              x = MW'(ls) << k;
              {s, c} = {s ^ c ^ x, MW'(((s & c) | (s & x) | (c & x)) << 1)};
              x = MW'(lc) << k;
              {s, c} = {s ^ c ^ x, MW'(((s & c) | (s & x) | (c & x)) << 1)};
            end
        end
        s2o_mult_d[j] = s + c;  // c = 0 for a power of two
      end
    end

    always_ff @(posedge clk_i or negedge rst_ni) begin
      if (!rst_ni) begin
        s1o_sign_q  <= '0;
        s1o_sig_q   <= '0;
        s1o_sh_q    <= '0;
        s1bo_sign_q <= '0;
        s1bo_a_q    <= '0;
        s2o_sign_q  <= '0;
        s2o_nu_q    <= '0;
        s2o_nv_q    <= '0;
        s2o_mult_q  <= '0;
      end else begin
        s1o_sign_q  <= s1o_sign_d;
        s1o_sig_q   <= s1o_sig_d;
        s1o_sh_q    <= s1o_sh_d;
        s1bo_sign_q <= s1o_sign_q;
        s1bo_a_q    <= s1bo_a_d;
        s2o_sign_q  <= s1bo_sign_q[1:0];
        s2o_nu_q    <= s2o_nu_d;
        s2o_nv_q    <= s2o_nv_d;
        s2o_mult_q  <= s2o_mult_d;
      end
    end

    // Output: per coordinate, the bin m = #{j in 1..h-1 : N * h >= j * L} and the field s | m.
    logic [2*DirBits-1:0] oct_d;
    always_comb begin
      logic [1:0][LW-2:0] n;
      logic [1:0][DirBits-1:0] f;
      n[0] = s2o_nu_q;
      n[1] = s2o_nv_q;
      for (int a = 0; a < 2; a++) begin
        logic [MW-1:0] nh;
        logic [7:0] m;
        nh = MW'(n[a]) << (DirBits - 1);
        m = '0;
        for (int j = 1; j < Half; j++) m += 8'(nh >= s2o_mult_q[j]);
        f[a] = DirBits'(m) | (DirBits'(s2o_sign_q[a]) << (DirBits - 1));
      end
      oct_d = {f[0], f[1]};  // u | v
    end

    logic grid_dir_unused;  // the grid direction fields: not used by this code
    assign grid_dir_unused = ^d_fields;
    assign d_key = oct_d;
  end else begin : gen_grid_dir
    assign d_key = d_fields;
  end

  if (Combine == CombineXor) begin : gen_xor
    assign key_o = KeyWidth'(o_fields) ^ KeyWidth'(d_key);
  end else begin : gen_concat
    assign key_o = {o_fields, d_key};
  end
  assign invalid_o = inv2_q;

  // ---------------------------------------------------------------------------------------------
  // Assertions
  // ---------------------------------------------------------------------------------------------
  // The pipeline has the stages hrpp_pkg declares (s1, s1b, s2; hrpp_top delays the ray's id
  // and query type by HashLatency beside it).
  localparam int unsigned Stages = 3;
  if (Stages != HashLatency) begin : gen_latency_check
    $error("hrpp_hash has %0d stages; hrpp_pkg::HashLatency declares %0d", Stages, HashLatency);
  end
  if (Precision < 1 || Precision > 23) begin : gen_precision_check
    $error("Precision must be 1..23");
  end
  if (ExpBits > 8) begin : gen_exp_bits_check
    $error("ExpBits must be 0..8");
  end
  if (OriginBits < 1 || OriginBits > 16) begin : gen_origin_bits_check
    $error("OriginBits must be 1..16");
  end
  if (DirBits < 1 || DirBits > 16) begin : gen_dir_bits_check
    $error("DirBits must be 1..16");
  end
  if (DirCode == DirOct && (Variant != HashImproved || DirBits > 8)) begin : gen_dir_code_check
    $error("DirCode = DirOct needs the improved variant and DirBits 1..8");
  end
  if (KeyWidth > 64) begin : gen_key_width_check
    $error("keys are at most 64 bits");
  end

endmodule

`default_nettype wire
