// The closed loop of a model file with a controller (issue 30; presets/models/README.md "Closed
// loops"): on the world's rows, in order, the world steps to row k and its sensors sample; an
// event that holds there ends the run before row k; the filter predicts and updates on row k as
// on a log; the controller computes its outputs from the estimate, saturates them, drives the
// world's inputs over the next interval and moves its own states.
#pragma once

#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/metrics.h"
#include "core/scenario.h"
#include "model/model_filter.h"
#include "model/model_result.h"

namespace kfw::model {

struct LoopRun {
  Dataset data;  // the world's columns with the controller's reference and outputs, to the end
  std::shared_ptr<ModelResult> result;  // the filter's run over the same rows
  int event = -1;                       // the event that ended the run (ModelSpec::events), or −1
  double event_t = std::numeric_limits<double>::quiet_NaN();  // the time of the row it held on
  std::vector<std::size_t> impulsive, sampled;                // per world sensor
  std::vector<double> first_at;  // per world event: its first row's time before the end, or NaN
};

// One closed-loop run at `values`. `quiet`: the noise-free loop (every random draw zero; the
// same rows). Errors as run_model_filter's; an event at the first row is an Error (exit 2).
// `name` names the dataset's source ("simulated NAME, seed S").
Expected<LoopRun> run_closed_loop(const ModelSpec& spec, const ParamValues& values,
                                  const FilterOptions& options, const RunControl& control,
                                  const std::string& name, bool quiet = false);

// The run of a closed-loop model: the loop at `values`, then its noise-free twin for the
// controller's `noise_free` columns (in the data and the result), and the loop's metrics:
// event.NAME_at_s per world event, impulsive_fraction.SENSOR per sensor with impulses.
Expected<LoopRun> run_loop_model(const ModelSpec& spec, const ParamValues& values,
                                 const FilterOptions& options, const RunControl& control,
                                 const std::string& name);
std::vector<MetricSpec> loop_metric_specs(const ModelSpec& spec);

// A closed-loop model filtering a log (its loop open, seed 003's replay): each world event
// evaluated on the log's truth columns (the world's truth map names them; a state without one
// reads NaN), reported as in a loop — event.NAME, event.NAME_at_s and a warning — without ending
// the run.
Status replay_events(const ModelSpec& spec, const ParamValues& values, const Dataset& d,
                     ModelResult& r);

// Keeps the first n rows of every per-row series of a run.
void truncate_result(ModelResult& r, std::size_t n);

}  // namespace kfw::model
