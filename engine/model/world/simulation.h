// One simulation of a model (or a world), row by row: the process on the sim.dt grid, the sensors
// on the grid (`every`) or on their clocks' ticks, a row wherever something is sampled. A plain
// simulation runs every row (simulate_model, model_sim.h); a closed loop (model/loop/) runs a
// row, lets the filter and the controller see it, drives the world's inputs, and runs the next.
// Internal to the model room.
#pragma once

#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/dataset.h"
#include "core/random.h"
#include "model/model_eval.h"
#include "model/world/model_world_noise.h"

namespace kfw::model::detail {

class Simulation {
 public:
  // `quiet`: every random draw is zero (x0, process, sensor noise, noise sources), no dropout, no
  // impulse, no outlier — the noise-free run of a closed loop. Clock ticks are kept.
  Simulation(const ModelSpec& spec, ModelEval& ev, double dt, std::uint64_t seed,
             std::size_t max_rows, bool quiet = false);

  Status prepare(double duration, std::size_t grid_rows);
  // The whole simulation: begin, every row, finish.
  Expected<Dataset> run(const std::string& source);

  // Row by row: the dataset's columns sized for every row (NaN), x0 drawn; then row r's values
  // (rows in order); then the outliers over the whole run.
  Status begin(Dataset& d, const std::string& source);
  Status row(std::size_t r, Dataset& d);
  Status finish(Dataset& d);
  std::size_t rows() const { return row_t_.size(); }
  double row_time(std::size_t r) const { return row_t_[r]; }

  // A world input set from outside (a controller's output), held until set again; it overrides
  // the input's `sim` expression from the next grid step on.
  void drive(std::size_t input, double value);
  // The first event that ends the run (ModelSpec::events) positive at the last row's state (the
  // row at time t), or −1; every event's first time is kept (first_at).
  int event_now(double t);
  // The time of the first row where event e held; NaN: never.
  double first_at(std::size_t e) const { return first_at_[e]; }
  // Samples of sensor c so far in bursts of impulses, and in all.
  std::size_t impulsive(std::size_t c) const { return impulsive_[c]; }
  std::size_t sampled(std::size_t c) const { return sampled_[c]; }

 private:
  Error fail(double t, const std::string& what) const;
  void inputs_at(double t);
  void set_row(double t);  // the model's symbols at a row: t, inputs, noise, row_x_
  // The mean process from x_ at t_j over dt, with the inputs and sources of step j (the model's
  // symbols left there, for process_noise); a failure names the time t_end.
  Expected<VecX> mean_step(double dt, double t_end);
  void wrap_angles(VecX& x) const;
  void apply_limits(VecX& x) const;
  Status grid_step();         // x_j → x_{j+1}, with process noise
  Status state_at(double t);  // row_x_: x_j moved on to t by the mean process
  Status sample(std::size_t c, std::size_t row, double t, Dataset& d);
  // Sensor c's impulses at this sample: true when it is impulsive (its roles written here).
  bool impulse(std::size_t c, std::size_t row, Dataset& d);
  Status prepare_loop_keys();
  Status add_outliers(Dataset& d);
  Status select_clocks();
  VecX draw(RandomStream& r, Eigen::Index m);

  std::size_t max_rows_;
  const ModelSpec& spec_;
  ModelEval& ev_;
  const double dt_;
  const std::uint64_t seed_;
  const bool quiet_;
  std::vector<double> vars_;  // the inputs' simulation expressions read these
  ExprGroup input_sim_;
  std::vector<double> u_;
  std::vector<double> driven_;
  std::vector<char> is_driven_;
  RandomStream x0_, process_;
  std::vector<RandomStream> channel_streams_, dropout_streams_, burst_streams_, impulse_streams_;
  std::optional<NoiseSources> noise_;
  MatX Lq_;
  bool lq_valid_ = false;
  std::vector<MatX> Lr_;
  std::vector<bool> lr_valid_;
  std::vector<double> dropout_;
  // Impulses per sensor: rate, ln(1 − 1/burst) (0: bursts of one), [lo, hi), samples left in the
  // burst under way, the flag column (or −1), and the counts.
  struct Impulses {
    double rate = 0, log_stay = 0, lo = 0, hi = 0;
    std::size_t left = 0;
    long long flag_col = -1;
  };
  std::vector<Impulses> impulses_;
  // No noise enters the process / sensor c (its covariance a matrix of zeros): no draw is made.
  bool quiet_process_ = false;
  std::vector<char> quiet_sensor_;
  std::vector<std::size_t> impulsive_, sampled_;
  std::vector<ModelEval::Limit> limits_;
  ExprGroup events_;
  std::vector<double> event_values_, first_at_;

  // Rows: their times, the grid step of each (or −1), and per clock the rows of its ticks.
  std::vector<double> row_t_;
  std::vector<long long> row_grid_;
  std::vector<std::vector<bool>> clock_rows_;
  std::vector<int> sensor_clock_;  // per channel: its clock this run (a choice selects), or −1

  std::size_t j_ = 0;  // the grid step of x_
  VecX x_, row_x_;
  std::vector<std::size_t> role_col_, truth_col_;
  std::size_t expr_col_ = 0;
  ExprGroup truth_exprs_;
  std::vector<double> truth_values_;
  std::vector<std::vector<Sample>> samples_;  // per channel: its samples kept
};

// A simulation set up at the values: its world's evaluator, the simulation prepared (rows, clocks,
// sources) and the dataset's source text ("simulated NAME, seed S").
struct PreparedSimulation {
  std::unique_ptr<ModelEval> ev;
  std::unique_ptr<Simulation> sim;
  std::string source;
};
Expected<PreparedSimulation> prepare_simulation(const ModelSpec& spec, const ParamValues& values,
                                                const std::string& name, bool quiet);

}  // namespace kfw::model::detail
