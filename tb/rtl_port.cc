#include "rtl_port.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include "hrpp/hardware/cycle_model_lanes.h"
#include "tb_dut.h"

namespace hrpp::tb {
namespace {

// The Verilated RTL in lockstep with its cycle model, as tb_run.cc runs them: one lane (hrpp_top
// and CycleModel) or, with kLanes, every lane of hrpp_lanes and LanesCycleModel.
template <typename M, bool kLanes>
class RtlPortModel final : public sim::PortModel {
  using Model = std::conditional_t<kLanes, LanesCycleModel, CycleModel>;

 public:
  RtlPortModel(const CycleConfig& cc, MismatchSink sink)
      : cc_(cc),
        w_{cc.id_bits, cc.table.node_bits, cc.table.nodes_per_entry},
        ctx_(std::make_unique<VerilatedContext>()),
        model_(cc),
        sink_(std::move(sink)),
        out_(size_t(kLanes ? cc.lanes : 1)) {
    dut_ = std::make_unique<M>(ctx_.get());
    if constexpr (kLanes) {
      // The start of tb_run.cc's run (as reset_dut): every lane idle, two cycles in reset.
      dut_->cfg_mode_i = static_cast<uint8_t>(cc_.mode);
      dut_->cfg_cell_exp_i = static_cast<uint16_t>(cc_.hash.origin_cell_exp) & 0x1FF;
      for (int l = 0; l < lanes(); ++l) apply_lane(dut_.get(), DutIn{}, l, w_);
      dut_->rst_ni = 0;
      for (int i = 0; i < 4; ++i) {
        dut_->clk_i = i & 1;
        dut_->eval();
      }
      dut_->clk_i = 0;
      dut_->rst_ni = 1;
      dut_->eval();
    } else {
      reset_dut(dut_.get(), cc_, [] {});
    }
    refresh();
  }
  ~RtlPortModel() override { dut_->final(); }

  int lanes() const override { return int(out_.size()); }
  DutOut outputs(int lane) override { return out_.at(size_t(lane)); }

  // tb_run.cc's cycle: the inputs applied with the clock low, then the rising edge; the cycle
  // model takes the same inputs.
  void tick(const std::vector<DutIn>& in) override {
    if constexpr (kLanes) {
      for (int l = 0; l < lanes(); ++l) apply_lane(dut_.get(), in.at(size_t(l)), l, w_);
    } else {
      apply(dut_.get(), in.at(0));
    }
    dut_->clk_i = 0;
    dut_->eval();
    dut_->clk_i = 1;
    dut_->eval();
    if constexpr (kLanes)
      model_.tick(in);
    else
      model_.tick(in.at(0));
    ++cycle_;
    if (error_.empty() && ctx_->gotFinish())
      error_ = "the RTL finished early (an assertion?) at cycle " + std::to_string(cycle_ - 1);
    if (error_.empty() && model_.cycle() != cycle_)
      error_ = "the cycle model is at cycle " + std::to_string(model_.cycle()) + ", the RTL at " +
               std::to_string(cycle_);
    refresh();
  }

  std::string error() const override {
    if (!error_.empty()) return error_;
    if (!model_.error().empty()) return "cycle model: " + model_.error();
    return {};
  }
  uint64_t mismatches() const override { return mismatches_; }

 private:
  // The outputs of this cycle (registered: they do not depend on this cycle's inputs), compared
  // once per cycle, every lane; a cycle in which any lane differs counts once.
  void refresh() {
    bool differs = false;
    for (int l = 0; l < lanes(); ++l) {
      DutOut exp;
      if constexpr (kLanes) {
        out_[size_t(l)] = read_lane(dut_.get(), l, w_);
        exp = model_.outputs(l);
      } else {
        out_[0] = read(dut_.get(), w_.k, w_.node_bits);
        exp = model_.outputs();
      }
      const std::string d = compare_outputs(exp, out_[size_t(l)], w_.k);
      if (d.empty() || differs) continue;
      differs = true;
      if (mismatches_ == 0 && sink_)
        sink_("cycle " + std::to_string(cycle_) + (kLanes ? ", lane " + std::to_string(l) : "") +
              ": " + d);
    }
    mismatches_ += differs;
  }

  CycleConfig cc_;
  LaneWidths w_;
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<M> dut_;
  Model model_;
  MismatchSink sink_;
  std::vector<DutOut> out_;
  uint64_t cycle_ = 0, mismatches_ = 0;
  std::string error_;
};

}  // namespace

std::unique_ptr<sim::PortModel> make_rtl_port_model(const std::string& config,
                                                    const CycleConfig& cc,
                                                    MismatchSink on_first_mismatch) {
  if (cc.lanes > 1)
    return with_lanes_model(config, [&]<typename M>() -> std::unique_ptr<sim::PortModel> {
      return std::make_unique<RtlPortModel<M, true>>(cc, std::move(on_first_mismatch));
    });
  return with_model(config, [&]<typename M>() -> std::unique_ptr<sim::PortModel> {
    return std::make_unique<RtlPortModel<M, false>>(cc, std::move(on_first_mismatch));
  });
}

}  // namespace hrpp::tb
