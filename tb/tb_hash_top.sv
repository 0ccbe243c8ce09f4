// Test harness for the hash unit: thirteen parameter sets side by side on the same inputs, each
// output HashLatency (hrpp_pkg) cycles after its inputs
// (tb_hash.cc compares each key with the C++ hash of docs/hash.md).
module tb_hash_top
  import hrpp_pkg::*;
(
  input  logic              clk_i,
  input  logic              rst_ni,
  input  logic [2:0][31:0]  org_i,
  input  logic [2:0][31:0]  dir_i,
  input  logic signed [8:0] cell_exp_i,
  output logic [12:0][63:0] key_o,
  output logic [12:0]       invalid_o
);
  // Keep in sync with kConfigs in tb_hash.cc.
  // 0-7: faithful and improved with the grid direction code; 8-11: improved with the octahedral
  // code (8: the `oct` configuration's hash, origin 3 / direction 3 bits, concatenated); 12: the
  // default configuration's (improved, grid, origin 3 / direction 2 bits, concatenated).
  localparam hash_variant_e V[13] = '{HashFaithful, HashFaithful, HashFaithful, HashFaithful,
                                      HashImproved, HashImproved, HashImproved, HashImproved,
                                      HashImproved, HashImproved, HashImproved, HashImproved,
                                      HashImproved};
  localparam int unsigned P[13] = '{6, 2, 10, 1, 6, 6, 6, 6, 6, 6, 6, 6, 6};
  localparam int unsigned E[13] = '{3, 2, 8, 0, 3, 3, 3, 3, 3, 3, 3, 3, 3};
  localparam int unsigned GO[13] = '{5, 5, 5, 5, 5, 16, 1, 10, 3, 5, 16, 1, 3};
  localparam int unsigned GD[13] = '{3, 3, 3, 3, 3, 16, 1, 8, 3, 1, 8, 4, 2};
  localparam combine_e C[13] = '{CombineXor, CombineConcat, CombineXor, CombineConcat,
                                 CombineConcat, CombineXor, CombineConcat, CombineXor,
                                 CombineConcat, CombineXor, CombineConcat, CombineXor,
                                 CombineConcat};
  localparam dir_code_e D[13] = '{DirGrid, DirGrid, DirGrid, DirGrid, DirGrid, DirGrid, DirGrid,
                                  DirGrid, DirOct, DirOct, DirOct, DirOct, DirGrid};

  for (genvar i = 0; i < 13; i++) begin : gen_hash
    localparam int unsigned KW = key_width(V[i], P[i], E[i], GO[i], GD[i], C[i], D[i]);
    logic [KW-1:0] key;
    hrpp_hash #(
      .Variant(V[i]), .Precision(P[i]), .ExpBits(E[i]), .OriginBits(GO[i]), .DirBits(GD[i]),
      .Combine(C[i]), .DirCode(D[i])
    ) u_hash (
      .clk_i, .rst_ni, .org_i, .dir_i, .cell_exp_i, .key_o(key), .invalid_o(invalid_o[i])
    );
    assign key_o[i] = 64'(key);
  end
endmodule
