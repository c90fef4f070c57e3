// A curve check: a particle's displacement (or velocity) along a direction against an analytical
// function of time; its value is the largest error over a scale (the kinds sliding_block and
// wedge_slide). Its numerical and analytical values now are two columns of series.csv.
#pragma once

#include <functional>

#include "polydem/run/checks.h"

namespace polydem::run {

class CurveCheck : public Check {
 public:
  using Curve = std::function<double(double time)>;
  /// `velocity`: compare the velocity (else the displacement); `relative_to_final`: the scale is
  /// the final analytical value (else the largest).
  CurveCheck(const setup::CheckSpec& spec, Uid uid, Curve analytic, bool velocity, Vec3 direction,
             bool relative_to_final);
  void observe(const sim::Simulation& sim, const Tracker& t) override;
  double value(sim::Simulation&) override;
  std::vector<std::pair<std::string, double>> seriesColumns(const sim::Simulation&) const override;
  std::vector<double> state() const override { return {numeric_, exact_, error_, scale_}; }
  void restore(const std::vector<double>& v) override;

 private:
  Uid uid_;
  Curve analytic_;
  bool velocity_;
  Vec3 direction_;
  bool relative_to_final_;
  double numeric_ = 0.0, exact_ = 0.0, error_ = 0.0, scale_ = 0.0;
};

}  // namespace polydem::run
