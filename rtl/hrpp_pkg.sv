`default_nettype none
// HRPP shared types and constants (docs/microarchitecture.md, docs/hash.md).
package hrpp_pkg;

  // Hash variants (docs/hash.md).
  typedef enum logic {
    HashFaithful = 1'b0,  // sign | top E exponent bits | top P mantissa bits
    HashImproved = 1'b1   // exact fixed-point grid
  } hash_variant_e;

  typedef enum logic {
    CombineXor    = 1'b0,
    CombineConcat = 1'b1
  } combine_e;

  // How closest-hit rays use predictions (cfg_mode_i).
  typedef enum logic [1:0] {
    ModeAnyHit       = 2'd0,  // every ray is an any-hit query
    ModeClosestExact = 2'd1,  // a predicted hit bounds the full walk
    ModeClosestSpec  = 2'd2   // a predicted hit is the answer
  } mode_e;

  // Skip decisions (skip_action_o).
  typedef enum logic [1:0] {
    ActFull   = 2'd0,  // walk from the root
    ActShrink = 2'd1,  // walk from the root with tfar bounded by the predicted hit
    ActSkip   = 2'd2   // the predicted hit is the answer: no walk from the root
  } action_e;

  // Ray kinds, as in the golden model (model/include/hrpp/ray.h): 0 primary, 1 shadow, 2 AO,
  // 3 reflection, 4 refraction, 5 diffuse.
  localparam logic [2:0] KindShadow = 3'd1;
  localparam logic [2:0] KindAo = 3'd2;

  function automatic logic kind_is_any_hit(logic [2:0] kind);
    return kind == KindShadow || kind == KindAo;
  endfunction

endpackage

`default_nettype wire
