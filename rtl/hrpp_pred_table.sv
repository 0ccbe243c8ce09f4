`default_nettype none
// HRPP predictor table: NumSets sets x NumWays ways x NodesPerEntry node ids, true LRU over ways
// (age counters), node ids in most-recently-used-first order (docs/hash.md, "Predictor table").
//
// Two copies of the table in block RAM, written together: the lookup copy serves one lookup
// per cycle, the update copy one read-modify-write per cycle. Timing (docs/microarchitecture.md):
//   lookup: L1 read address | L2 RAM data | L3 RAM data registered, collision select, tag
//           compare | L4 way select, outputs registered: lk_valid_o four cycles after lk_valid_i.
//   update: T0 read address | T1 RAM data | T2 RAM data registered | C1 forward, match |
//           C2 select the way | C3 new row | W write to both copies.
// A lookup sees every write presented in the cycle of its read or earlier. An update whose set
// equals that of an update accepted in either of the two previous cycles waits (up_ready_o low);
// every other hazard is forwarded, so one lookup and one update per cycle are sustained.
// After reset the table clears itself, one set per cycle (NumSets cycles, init_done_o low).
module hrpp_pred_table
  import hrpp_pkg::*;
#(
  parameter int unsigned NumSets = 256,       /// sets, a power of two
  parameter int unsigned NumWays = 4,         /// ways, 2..16
  parameter int unsigned NodesPerEntry = 2,   /// node ids per way (K), 1..8
  parameter int unsigned NodeIdWidth = 17,    /// bits of a node id
  parameter int unsigned TagBits = 12,        /// stored tag bits
  parameter bit InjectFault = 1'b0,           /// test only: a one-bit fault in the node update
  localparam int unsigned IdxW = $clog2(NumSets),
  localparam int unsigned CountW = $clog2(NodesPerEntry + 1),
  localparam int unsigned AgeW = $clog2(NumWays)
) (
  input  logic                                       clk_i,
  input  logic                                       rst_ni,
  output logic                                       init_done_o,  /// the reset clear is over
  // Lookup (never stalls)
  input  logic                                       lk_valid_i,
  input  logic [IdxW-1:0]                            lk_idx_i,
  input  logic [TagBits-1:0]                         lk_tag_i,
  output logic                                       lk_valid_o,
  output logic [CountW-1:0]                          lk_count_o,  /// 0: no prediction
  output logic [NodesPerEntry-1:0][NodeIdWidth-1:0]  lk_nodes_o,  /// MRU first
  // Update: node_i becomes the most recently used node of the tag's entry
  input  logic                                       up_valid_i,
  output logic                                       up_ready_o,
  input  logic [IdxW-1:0]                            up_idx_i,
  input  logic [TagBits-1:0]                         up_tag_i,
  input  logic [NodeIdWidth-1:0]                     up_node_i
);

  typedef struct packed {
    logic                                      valid;
    logic [TagBits-1:0]                        tag;
    logic [CountW-1:0]                         count;
    logic [NodesPerEntry-1:0][NodeIdWidth-1:0] nodes;  // [0] = most recently used
    logic [AgeW-1:0]                           age;    // 0 = most recently used way
  } way_t;
  typedef way_t [NumWays-1:0] row_t;
  localparam int unsigned RowW = $bits(row_t);

  // The row every set holds after reset: all ways invalid, way i has age i.
  function automatic row_t init_row();
    row_t r;
    r = '0;
    for (int w = 0; w < NumWays; w++) r[w].age = AgeW'(w);
    return r;
  endfunction

  // ---------------------------------------------------------------------------------------------
  // Reset clear sequence and the write port
  // ---------------------------------------------------------------------------------------------
  logic            clearing_q;
  logic [IdxW-1:0] clear_idx_q;
  logic            we;
  logic [IdxW-1:0] waddr;
  row_t            wdata;
  // W stage
  logic            w_valid_q;
  logic [IdxW-1:0] w_idx_q;
  row_t            w_row_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      clearing_q  <= 1'b1;
      clear_idx_q <= '0;
    end else if (clearing_q) begin
      clear_idx_q <= clear_idx_q + 1'b1;
      if (clear_idx_q == IdxW'(NumSets - 1)) clearing_q <= 1'b0;
    end
  end
  assign init_done_o = !clearing_q;

  assign we    = clearing_q || w_valid_q;
  assign waddr = clearing_q ? clear_idx_q : w_idx_q;
  assign wdata = clearing_q ? init_row() : w_row_q;

  // ---------------------------------------------------------------------------------------------
  // Memories
  // ---------------------------------------------------------------------------------------------
  logic [RowW-1:0] lk_rdata, up_rdata;
  logic [IdxW-1:0] up_raddr;
  logic            up_re;

  hrpp_ram_1r1w #(.Depth(NumSets), .Width(RowW)) u_lookup_ram (
    .clk_i, .re_i(lk_valid_i), .raddr_i(lk_idx_i), .rdata_o(lk_rdata),
    .we_i(we), .waddr_i(waddr), .wdata_i(wdata)
  );
  hrpp_ram_1r1w #(.Depth(NumSets), .Width(RowW)) u_update_ram (
    .clk_i, .re_i(up_re), .raddr_i(up_raddr), .rdata_o(up_rdata),
    .we_i(we), .waddr_i(waddr), .wdata_i(wdata)
  );

  // ---------------------------------------------------------------------------------------------
  // Lookup pipeline
  // ---------------------------------------------------------------------------------------------
  // Every block-RAM output goes straight into a register (its clock-to-output delay is most of
  // a cycle); the collision select, the tag compare and the way select follow in later stages.
  // L2: the RAM data; the row written in the cycle of the read, and whether it collided.
  logic               l2_valid_q, l2_collide_q;
  logic [TagBits-1:0] l2_tag_q;
  row_t               l2_wrow_q;
  // L3: the RAM data registered, beside the collision flag and row.
  logic               l3_valid_q, l3_collide_q;
  logic [TagBits-1:0] l3_tag_q;
  row_t               l3_ram_q, l3_wrow_q;
  // L4: per way, whether it matches, and its count and nodes.
  logic                                      l4_valid_q;
  logic [NumWays-1:0]                        l4_match_q;
  logic [NumWays-1:0][CountW-1:0]            l4_count_q;
  logic [NumWays-1:0][NodesPerEntry-1:0][NodeIdWidth-1:0] l4_nodes_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      l2_valid_q   <= 1'b0;
      l2_collide_q <= 1'b0;
      l2_tag_q     <= '0;
      l2_wrow_q    <= '0;
      l3_valid_q   <= 1'b0;
      l3_collide_q <= 1'b0;
      l3_tag_q     <= '0;
      l3_ram_q     <= '0;
      l3_wrow_q    <= '0;
    end else begin
      l2_valid_q   <= lk_valid_i;
      l2_collide_q <= lk_valid_i && we && waddr == lk_idx_i;
      l2_tag_q     <= lk_tag_i;
      l2_wrow_q    <= wdata;
      l3_valid_q   <= l2_valid_q;
      l3_collide_q <= l2_collide_q;
      l3_tag_q     <= l2_tag_q;
      l3_ram_q     <= row_t'(lk_rdata);
      l3_wrow_q    <= l2_wrow_q;
    end
  end

  // L3: the row (the colliding write, else the RAM data); per way, tag match.
  row_t               l3_row;
  logic [NumWays-1:0] l3_match;
  always_comb begin
    l3_row = l3_collide_q ? l3_wrow_q : l3_ram_q;
    for (int w = 0; w < NumWays; w++)
      l3_match[w] = l3_row[w].valid && l3_row[w].tag == l3_tag_q;
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      l4_valid_q <= 1'b0;
      l4_match_q <= '0;
      l4_count_q <= '0;
      l4_nodes_q <= '0;
    end else begin
      l4_valid_q <= l3_valid_q;
      l4_match_q <= l3_valid_q ? l3_match : '0;
      for (int w = 0; w < NumWays; w++) begin
        l4_count_q[w] <= l3_row[w].count;
        l4_nodes_q[w] <= l3_row[w].nodes;
      end
    end
  end

  // L4: the matching way (at most one matches) -> registered outputs (zero without a match).
  logic [CountW-1:0]                         lk_count_d;
  logic [NodesPerEntry-1:0][NodeIdWidth-1:0] lk_nodes_d;
  always_comb begin
    lk_count_d = '0;
    lk_nodes_d = '0;
    for (int w = 0; w < NumWays; w++) begin
      lk_count_d |= l4_count_q[w] & {CountW{l4_match_q[w]}};
      lk_nodes_d |= l4_nodes_q[w] & {(NodesPerEntry * NodeIdWidth){l4_match_q[w]}};
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      lk_valid_o <= 1'b0;
      lk_count_o <= '0;
      lk_nodes_o <= '0;
    end else begin
      lk_valid_o <= l4_valid_q;
      lk_count_o <= lk_count_d;
      lk_nodes_o <= lk_nodes_d;
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Update pipeline
  // ---------------------------------------------------------------------------------------------
  // T0: the accepted request; its read address goes to the update RAM.
  logic                   t0_valid_q, t1_valid_q, t2_valid_q, c1_valid_q, c2_valid_q, c3_valid_q;
  logic [IdxW-1:0]        t0_idx_q, t1_idx_q, t2_idx_q, c1_idx_q, c2_idx_q, c3_idx_q;
  logic [TagBits-1:0]     t0_tag_q, t1_tag_q, t2_tag_q, c1_tag_q, c2_tag_q;
  logic [NodeIdWidth-1:0] t0_node_q, t1_node_q, t2_node_q, c1_node_q, c2_node_q, c3_node_q;
  // The rows written one and two cycles ago (for forwarding), and the set of the first.
  logic                   h1_valid_q;
  logic [IdxW-1:0]        h1_idx_q;
  row_t                   h1_row_q, h2_row_q;
  // T1 -> T2 -> C1: the RAM data, registered twice. The first register has no other load, so
  // it sits beside the block RAM; the long route to C1's logic gets a cycle of its own.
  row_t                   t2_ram_q, c1_ram_q;
  // The newest write C1's RAM read cannot see (selected in T2), and per way whether to use it
  // (one copy per way: each drives a way's bits of C1's 2:1 mux).
  row_t                   c1_fwd_row_q;
  (* keep *) logic [NumWays-1:0] c1_use_fwd_q;
  // T1 -> T2: which rows T2 forwards (set compares one cycle ahead; one copy per way).
  (* keep *) logic [NumWays-1:0] t2_fwd_c3_q, t2_fwd_w_q, t2_fwd_h1_q, t2_fwd_h2_q;
  // C1 -> C2: the current row and, per way, one-hot decisions (see C1).
  row_t                   c2_row_q;
  logic [NumWays-1:0]     c2_match_q, c2_first_inv_q, c2_oldest_q;
  logic                   c2_any_match_q, c2_any_inv_q;
  logic [NumWays-1:0][NodesPerEntry-1:0][(NodeIdWidth+1)/2-1:0] c2_node_eq_part_q;
  // C2 -> C3: the selected way (cleared if newly allocated), which of its nodes equal the node.
  row_t                   c3_row_q;
  logic [NumWays-1:0]     c3_sel_q;   // one-hot way to update
  way_t                   c3_way_q;
  logic [NodesPerEntry-1:0] c3_node_eq_q;
  row_t                   c3_new_row;  // C3's result

  // An update waits while the update accepted in either of the two previous cycles has its set:
  // C1 needs that update's new row, which leaves C3 only two cycles after its own C1.
  assign up_ready_o = !clearing_q && !(t0_valid_q && t0_idx_q == up_idx_i) &&
                      !(t1_valid_q && t1_idx_q == up_idx_i);
  assign up_re      = t0_valid_q;
  assign up_raddr   = t0_idx_q;

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      t0_valid_q  <= 1'b0;
      t0_idx_q    <= '0;
      t0_tag_q    <= '0;
      t0_node_q   <= '0;
      t1_valid_q  <= 1'b0;
      t1_idx_q    <= '0;
      t1_tag_q    <= '0;
      t1_node_q   <= '0;
      t2_valid_q  <= 1'b0;
      t2_idx_q    <= '0;
      t2_tag_q    <= '0;
      t2_node_q   <= '0;
      t2_ram_q    <= '0;
      c1_valid_q  <= 1'b0;
      c1_idx_q    <= '0;
      c1_tag_q    <= '0;
      c1_node_q   <= '0;
      c1_ram_q    <= '0;
      c1_fwd_row_q <= '0;
      c1_use_fwd_q <= '0;
      t2_fwd_c3_q  <= '0;
      t2_fwd_w_q   <= '0;
      t2_fwd_h1_q  <= '0;
      t2_fwd_h2_q  <= '0;
      h1_valid_q  <= 1'b0;
      h1_idx_q    <= '0;
      h1_row_q    <= '0;
      h2_row_q    <= '0;
    end else begin
      t0_valid_q <= up_valid_i && up_ready_o;
      t0_idx_q   <= up_idx_i;
      t0_tag_q   <= up_tag_i;
      t0_node_q  <= up_node_i;
      t1_valid_q <= t0_valid_q;
      t1_idx_q   <= t0_idx_q;
      t1_tag_q   <= t0_tag_q;
      t1_node_q  <= t0_node_q;
      t2_valid_q <= t1_valid_q;
      t2_idx_q   <= t1_idx_q;
      t2_tag_q   <= t1_tag_q;
      t2_node_q  <= t1_node_q;
      t2_ram_q   <= row_t'(up_rdata);
      c1_valid_q <= t2_valid_q;
      c1_idx_q   <= t2_idx_q;
      c1_tag_q   <= t2_tag_q;
      c1_node_q  <= t2_node_q;
      c1_ram_q   <= t2_ram_q;
      // C1 needs the newest of four writes its RAM read (presented in T0, three cycles before
      // C1) cannot have seen: the row C3 computes now (written while C1 runs), the row W writes
      // now, and the rows written one (h1) and two (h2) cycles ago. The set compares are made in
      // T1 against the stages those rows are in one cycle earlier.
      t2_fwd_c3_q <= {NumWays{c2_valid_q && c2_idx_q == t1_idx_q}};
      t2_fwd_w_q  <= {NumWays{c3_valid_q && c3_idx_q == t1_idx_q}};
      t2_fwd_h1_q <= {NumWays{w_valid_q && w_idx_q == t1_idx_q}};
      t2_fwd_h2_q <= {NumWays{h1_valid_q && h1_idx_q == t1_idx_q}};
      c1_use_fwd_q <= t2_fwd_c3_q | t2_fwd_w_q | t2_fwd_h1_q | t2_fwd_h2_q;
      for (int w = 0; w < NumWays; w++)
        c1_fwd_row_q[w] <= t2_fwd_c3_q[w] ? c3_new_row[w] : t2_fwd_w_q[w] ? w_row_q[w] :
                           t2_fwd_h1_q[w] ? h1_row_q[w] : h2_row_q[w];
      h1_valid_q <= w_valid_q;
      h1_idx_q   <= w_idx_q;
      h1_row_q   <= w_row_q;
      h2_row_q   <= h1_row_q;
    end
  end

  // C1: the current row (newest write first); per way: tag match (at most one way matches),
  // the first invalid way and the least recently used way, all one-hot, so C2 only selects;
  // and the node compare's first level (two bits at a time), finished in C2.
  localparam int unsigned EqGroups = (NodeIdWidth + 1) / 2;
  typedef logic [NumWays-1:0][NodesPerEntry-1:0][EqGroups-1:0] node_eq_part_t;
  row_t               c1_row;
  logic [NumWays-1:0] c1_match, c1_invalid, c1_first_invalid, c1_oldest;
  node_eq_part_t      c1_node_eq_part;
  always_comb begin
    for (int w = 0; w < NumWays; w++) c1_row[w] = c1_use_fwd_q[w] ? c1_fwd_row_q[w] : c1_ram_q[w];
    for (int w = 0; w < NumWays; w++) begin
      c1_match[w]   = c1_row[w].valid && c1_row[w].tag == c1_tag_q;
      c1_invalid[w] = !c1_row[w].valid;
      c1_oldest[w]  = c1_row[w].age == AgeW'(NumWays - 1);
      for (int i = 0; i < NodesPerEntry; i++)
        for (int g = 0; g < EqGroups; g++)
          c1_node_eq_part[w][i][g] = 2'(c1_row[w].nodes[i] >> (2 * g)) == 2'(c1_node_q >> (2 * g));
    end
    for (int w = 0; w < NumWays; w++) begin
      c1_first_invalid[w] = c1_invalid[w];
      for (int v = 0; v < w; v++)
        if (c1_invalid[v]) c1_first_invalid[w] = 1'b0;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      c2_valid_q       <= 1'b0;
      c2_idx_q         <= '0;
      c2_tag_q         <= '0;
      c2_node_q        <= '0;
      c2_row_q         <= '0;
      c2_match_q       <= '0;
      c2_any_match_q   <= 1'b0;
      c2_first_inv_q   <= '0;
      c2_any_inv_q     <= 1'b0;
      c2_oldest_q      <= '0;
      c2_node_eq_part_q <= '0;
    end else begin
      c2_valid_q       <= c1_valid_q;
      c2_idx_q         <= c1_idx_q;
      c2_tag_q         <= c1_tag_q;
      c2_node_q        <= c1_node_q;
      c2_row_q         <= c1_row;
      c2_match_q       <= c1_match;
      c2_any_match_q   <= |c1_match;
      c2_first_inv_q   <= c1_first_invalid;
      c2_any_inv_q     <= |c1_invalid;
      c2_oldest_q      <= c1_oldest;
      c2_node_eq_part_q <= c1_node_eq_part;
    end
  end

  // C2: the way to update: the matching one, else the first invalid one, else the least
  // recently used one; that way (cleared when newly allocated) and its node matches.
  logic [NumWays-1:0]       c2_sel;
  way_t                     c2_way;
  logic [NodesPerEntry-1:0] c2_way_node_eq;
  logic [NumWays-1:0][NodesPerEntry-1:0] c2_node_eq;  // per way: node i equals the node
  always_comb begin
    c2_sel = c2_any_match_q ? c2_match_q : c2_any_inv_q ? c2_first_inv_q : c2_oldest_q;
    for (int w = 0; w < NumWays; w++)
      for (int i = 0; i < NodesPerEntry; i++)
        c2_node_eq[w][i] = CountW'(i) < c2_row_q[w].count && &c2_node_eq_part_q[w][i];
    c2_way = '0;
    c2_way_node_eq = '0;
    for (int w = 0; w < NumWays; w++) begin
      c2_way         |= c2_row_q[w] & {$bits(way_t){c2_sel[w]}};
      c2_way_node_eq |= c2_node_eq[w] & {NodesPerEntry{c2_sel[w]}};
    end
    if (!c2_any_match_q) begin  // a newly allocated way (its age stays for the LRU update)
      c2_way.valid   = 1'b1;
      c2_way.tag     = c2_tag_q;
      c2_way.count   = '0;
      c2_way.nodes   = '0;
      c2_way_node_eq = '0;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      c3_valid_q   <= 1'b0;
      c3_idx_q     <= '0;
      c3_node_q    <= '0;
      c3_row_q     <= '0;
      c3_sel_q     <= '0;
      c3_way_q     <= '0;
      c3_node_eq_q <= '0;
    end else begin
      c3_valid_q   <= c2_valid_q;
      c3_idx_q     <= c2_idx_q;
      c3_node_q    <= c2_node_q;
      c3_row_q     <= c2_row_q;
      c3_sel_q     <= c2_sel;
      c3_way_q     <= c2_way;
      c3_node_eq_q <= c2_way_node_eq;
    end
  end

  // C3: promote the node in the selected way, age every younger way by one.
  way_t                     c3_new_way;
  logic [CountW-1:0]        c3_pos;
  always_comb begin
    // Position of the node in the list, or where it is inserted.
    c3_pos = c3_way_q.count < CountW'(NodesPerEntry) ? c3_way_q.count
                                                     : CountW'(NodesPerEntry - 1);
    for (int i = NodesPerEntry - 1; i >= 0; i--)
      if (c3_node_eq_q[i]) c3_pos = CountW'(i);
    c3_new_way = c3_way_q;
    if (!(|c3_node_eq_q) && c3_way_q.count < CountW'(NodesPerEntry))
      c3_new_way.count = c3_way_q.count + 1'b1;
    for (int i = 1; i < NodesPerEntry; i++)
      if (CountW'(i) <= c3_pos) c3_new_way.nodes[i] = c3_way_q.nodes[i-1];
    // InjectFault (test only): the lowest bit of a node id written to way 0 is flipped.
    c3_new_way.nodes[0] = c3_node_q ^ NodeIdWidth'(InjectFault && c3_sel_q[0]);
    c3_new_way.age = '0;
    for (int w = 0; w < NumWays; w++) begin
      c3_new_row[w] = c3_sel_q[w] ? c3_new_way : c3_row_q[w];
      if (!c3_sel_q[w] && c3_row_q[w].age < c3_way_q.age)
        c3_new_row[w].age = c3_row_q[w].age + 1'b1;
    end
  end

  always_ff @(posedge clk_i or negedge rst_ni) begin
    if (!rst_ni) begin
      w_valid_q <= 1'b0;
      w_idx_q   <= '0;
      w_row_q   <= '0;
    end else begin
      w_valid_q <= c3_valid_q;
      w_idx_q   <= c3_idx_q;
      w_row_q   <= c3_new_row;
    end
  end

  // ---------------------------------------------------------------------------------------------
  // Assertions
  // ---------------------------------------------------------------------------------------------
  initial begin : gen_param_checks
    assert (NumSets >= 2 && (NumSets & (NumSets - 1)) == 0)
      else $fatal(1, "NumSets must be a power of two >= 2");
    assert (NumWays >= 2 && NumWays <= 16) else $fatal(1, "NumWays must be 2..16");
    assert (NodesPerEntry >= 1 && NodesPerEntry <= 8) else $fatal(1, "NodesPerEntry: 1..8");
    assert (TagBits >= 1 && TagBits <= 64) else $fatal(1, "TagBits must be 1..64");
  end

`ifndef SYNTHESIS
  // At most one way matches a tag (an entry is only allocated when none does).
  OneWayMatches_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      c1_valid_q |-> $onehot0(c1_match));
  // The selected way is one-hot.
  SelOneHot_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      c3_valid_q |-> $onehot(c3_sel_q));
  // Updates of one set are at least three cycles apart (the interlock).
  SameSetSpacing_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      c1_valid_q |-> !(c2_valid_q && c2_idx_q == c1_idx_q) &&
                     !(c3_valid_q && c3_idx_q == c1_idx_q));
  // At most one way matches in a lookup too.
  LookupOneMatch_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      $onehot0(l4_match_q));
  // Lookup outputs are never X.
  LookupKnown_A: assert property (@(posedge clk_i) disable iff (!rst_ni)
      lk_valid_o |-> !$isunknown({lk_count_o, lk_nodes_o}));
`endif

endmodule

`default_nettype wire
