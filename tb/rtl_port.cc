#include "rtl_port.h"

#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "hrpp/hardware/cycle_model_lanes.h"
#include "tb_dut.h"

namespace hrpp::tb {
namespace {

template <typename M>
class RtlPortModel final : public sim::PortModel {
 public:
  RtlPortModel(const CycleConfig& cc, MismatchSink sink)
      : cc_(cc), ctx_(std::make_unique<VerilatedContext>()), model_(cc), sink_(std::move(sink)) {
    dut_ = std::make_unique<M>(ctx_.get());
    reset_dut(dut_.get(), cc_, [] {});
    refresh();
  }
  ~RtlPortModel() override { dut_->final(); }

  DutOut outputs(int /*lane*/) override { return out_; }

  // tb_run.cc's cycle: the inputs applied with the clock low, then the rising edge; the cycle
  // model takes the same inputs.
  void tick(const std::vector<DutIn>& ins) override {
    const DutIn& in = ins.at(0);
    apply(dut_.get(), in);
    dut_->clk_i = 0;
    dut_->eval();
    dut_->clk_i = 1;
    dut_->eval();
    model_.tick(in);
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
  // once per cycle.
  void refresh() {
    out_ = read(dut_.get(), cc_.table.nodes_per_entry, cc_.table.node_bits);
    const std::string d = compare_outputs(model_.outputs(), out_, cc_.table.nodes_per_entry);
    if (d.empty()) return;
    if (mismatches_++ == 0 && sink_) sink_("cycle " + std::to_string(cycle_) + ": " + d);
  }

  CycleConfig cc_;
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<M> dut_;
  CycleModel model_;
  MismatchSink sink_;
  DutOut out_;
  uint64_t cycle_ = 0, mismatches_ = 0;
  std::string error_;
};

// The multi-lane RTL (hrpp_lanes) in lockstep with LanesCycleModel, as tb_run.cc's lanes run.
template <typename M>
class RtlLanesPortModel final : public sim::PortModel {
 public:
  RtlLanesPortModel(const CycleConfig& cc, MismatchSink sink)
      : cc_(cc),
        w_{cc.id_bits, cc.table.node_bits, cc.table.nodes_per_entry},
        ctx_(std::make_unique<VerilatedContext>()),
        model_(cc),
        sink_(std::move(sink)),
        out_(size_t(cc.lanes)) {
    dut_ = std::make_unique<M>(ctx_.get());
    // The start of tb_run.cc's lanes run: every lane idle, two cycles in reset.
    dut_->cfg_mode_i = static_cast<uint8_t>(cc_.mode);
    dut_->cfg_cell_exp_i = static_cast<uint16_t>(cc_.hash.origin_cell_exp) & 0x1FF;
    for (int l = 0; l < cc_.lanes; ++l) apply_lane(dut_.get(), DutIn{}, l, w_);
    dut_->rst_ni = 0;
    for (int i = 0; i < 4; ++i) {
      dut_->clk_i = i & 1;
      dut_->eval();
    }
    dut_->clk_i = 0;
    dut_->rst_ni = 1;
    dut_->eval();
    refresh();
  }
  ~RtlLanesPortModel() override { dut_->final(); }

  int lanes() const override { return cc_.lanes; }
  DutOut outputs(int lane) override { return out_.at(size_t(lane)); }

  void tick(const std::vector<DutIn>& in) override {
    for (int l = 0; l < cc_.lanes; ++l) apply_lane(dut_.get(), in.at(size_t(l)), l, w_);
    dut_->clk_i = 0;
    dut_->eval();
    dut_->clk_i = 1;
    dut_->eval();
    model_.tick(in);
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
  void refresh() {
    bool differs = false;
    for (int l = 0; l < cc_.lanes; ++l) {
      out_[size_t(l)] = read_lane(dut_.get(), l, w_);
      const std::string d = compare_outputs(model_.outputs(l), out_[size_t(l)], w_.k);
      if (d.empty() || differs) continue;
      differs = true;
      if (mismatches_ == 0 && sink_)
        sink_("cycle " + std::to_string(cycle_) + ", lane " + std::to_string(l) + ": " + d);
    }
    mismatches_ += differs;
  }

  CycleConfig cc_;
  LaneWidths w_;
  std::unique_ptr<VerilatedContext> ctx_;
  std::unique_ptr<M> dut_;
  LanesCycleModel model_;
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
      return std::make_unique<RtlLanesPortModel<M>>(cc, std::move(on_first_mismatch));
    });
  return with_model(config, [&]<typename M>() -> std::unique_ptr<sim::PortModel> {
    return std::make_unique<RtlPortModel<M>>(cc, std::move(on_first_mismatch));
  });
}

}  // namespace hrpp::tb
