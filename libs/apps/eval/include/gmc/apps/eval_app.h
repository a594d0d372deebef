#pragma once
#include "gmc/apps/app.h"

namespace gmc::apps {

/// gmc-eval --gt FILE --est FILE [--gt-frame camera|bonn] [--json OUT.json] [--plot OUT.png]
///          [--gt-out OUT.txt]
class EvalApp : public App {
 public:
  void initialize(const std::vector<std::string>& args) override;
  int run() override;

 private:
  std::string gt_, est_, gt_frame_ = "camera", json_, plot_, gt_out_;
};

}  // namespace gmc::apps
