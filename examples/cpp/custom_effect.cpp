// Register a physical effect of your own, written in C++, and let the diagnosis test it: a drag that grows with
// the square of the speed, -c m |v| v (and -c I |omega| omega), which the library does not ship. The same effect
// in Python is examples/custom_effect.py.
//
//   custom_effect FILE...      diagnoses the pushes (one object on one surface) and prints what was selected
//
// Build against an installed pushpred (examples/cpp/CMakeLists.txt: find_package(pushpred)), or inside the
// pushpred build tree, where it is the target `custom_effect`.
#include <cmath>
#include <iostream>
#include <memory>

#include "pushpred/diagnosis/diagnosis.hpp"
#include "pushpred/reports/diagnosis_report.hpp"

namespace {

class QuadraticDrag final : public pushpred::ForceLawEffect {
 public:
  std::string kind() const override { return "quadratic_drag"; }
  std::string description() const override { return "drag -c (m |v| v, I |omega| omega)"; }
  std::vector<pushpred::EffectParameter> parameters() const override { return {{"c", "1/m"}}; }
  // Tested against a Coulomb friction law, as the library's own friction refinements are.
  bool needs_friction_base() const override { return true; }
  // The generalized force per unit of c: f_x, f_y [N], torque [N m]; state in SI, frame {R}.
  Eigen::Vector3d unit_force(int /*parameter*/, double /*setting*/, const pushpred::EffectState& s,
                             const pushpred::ShapeInfo& shape) const override {
    const double speed = std::hypot(s.velocity(0), s.velocity(1));
    return -Eigen::Vector3d(shape.mass_kg * speed * s.velocity(0), shape.mass_kg * speed * s.velocity(1),
                            shape.inertia_kgm2 * std::abs(s.velocity(2)) * s.velocity(2));
  }
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2) {
    std::cerr << "usage: custom_effect FILE...  (pushes of one object on one surface)\n";
    return 2;
  }
  try {
    std::vector<pushpred::SynchronisedPush> pushes;
    for (int i = 1; i < argc; ++i) pushes.push_back(pushpred::load_push(argv[i]));
    pushpred::EffectLibrary library = pushpred::EffectLibrary::standard();
    library.register_effect(std::make_unique<QuadraticDrag>());
    const pushpred::DiagnosisResult result = pushpred::diagnose(pushes, library);
    for (const auto& e : result.effects)
      if (e.kind == "quadratic_drag")
        std::cout << "quadratic_drag: " << (e.selected ? "selected" : "not selected") << ", score " << e.score
                  << (e.note.empty() ? "" : " (" + e.note + ")") << "\n";
    std::cout << pushpred::diagnosis_summary_text(result);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "custom_effect: " << e.what() << "\n";
    return 1;
  }
}
