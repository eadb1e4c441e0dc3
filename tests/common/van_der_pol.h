// A Van der Pol oscillator as a model file (issue 27's example of a model without a scale
// group): nonlinear f by Euler steps, the position measured, truth for both states.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace kfw::testing {

// `flags`: the text spliced into the q and sigma entries (", \"tunable\": true", or "").
inline nlohmann::json van_der_pol_preset(const std::string& flags = "") {
  const std::string text = R"json({
    "format": "kfw-preset", "version": 2, "scenario": "model", "title": "Van der Pol",
    "parameters": {
      "mu": {"value": 1.0, "min": 0.1, "max": 5, "unit": "", "label": "μ, damping"},
      "q": {"value": 0.5, "min": 1e-4, "max": 1e3, "unit": "1/s³", "scale": "log",
            "label": "q, process noise density")json" +
                           flags + R"json(},
      "sigma": {"value": 0.2, "min": 1e-4, "max": 1e2, "unit": "", "scale": "log",
                "label": "σ, position noise")json" +
                           flags + R"json(},
      "P0_x": {"value": 1, "min": 1e-6, "max": 1e6, "scale": "log"},
      "x10": {"value": 2, "min": -10, "max": 10},
      "sim.dt": {"value": 0.05, "min": 1e-3, "max": 1, "unit": "s", "scale": "log"},
      "sim.duration": {"value": 30, "min": 1, "max": 600, "unit": "s"}
    },
    "model": {
      "version": 1,
      "states": [{"name": "x1", "unit": ""}, {"name": "x2", "unit": "1/s"}],
      "x0": ["x10", "0"],
      "P0": ["P0_x", "P0_x"],
      "process": {
        "f": ["x1 + dt*x2", "x2 + dt*(mu*(1 - x1^2)*x2 - x1)"],
        "Q": [["q*dt^3/3", "q*dt^2/2"], ["q*dt^2/2", "q*dt"]]
      },
      "measurements": {"pos": {"roles": [{"name": "z", "unit": ""}], "h": ["x1"],
                               "R": ["sigma^2"]}},
      "truth": {"x1": "x1_true", "x2": "x2_true"},
      "primary": "x1"
    }
  })json";
  return nlohmann::json::parse(text);
}

}  // namespace kfw::testing
