// Seed 003: the closed ball-and-beam loop (eq. 11, Fig. 6, Table 1) driven by the ball tracking
// filter's estimate, with a contact-type position sensor whose contact is lost at random, and an
// open-loop replay of the same filter over a recorded log.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "core/dataset.h"
#include "core/expected.h"
#include "core/scenario.h"
#include "oracles/ballbeam/ball_tracker.h"

namespace kfw::ballbeam {

// Linearised beam and ball (seed 003, eq. 11, Table 1): θ̈ = a1 θ̇ + a2 x + b1 V, ẍ = a3 θ.
struct Plant {
  double a1 = -31.21;  // 1/s
  double a2 = -3.05;   // rad/(s² m)
  double a3 = 4.80;    // m/(s² rad)
  double b1 = 33.88;   // rad/(s² V)
};

// Beam-angle PID and ball-position PD (seed 003, Fig. 6, Table 1):
// V = Kp(θc − θ) + KI ∫(θc − θ) dt − KD θ̇,  θc = Kx(xc − x̂) − Kv x̂̇.
struct Controller {
  double Kp = 62.63, KI = 17.53, KD = 0.09, Kx = 0.73, Kv = 1.45;
};

// The contact-type sensor: a nichrome wire across the beam, read as a voltage divider.
struct SensorModel {
  double beam_length_m = 0.4;  // wire length; x = 0 at the pivot, the wire spans ±L/2
  double Vcc_V = 5.0;
  // Divider output for a reading at x (contact kept), V = Vcc (1/2 + x/L) (seed 003, eq. 11 of
  // §III).
  double volts(double x_m) const { return Vcc_V * (0.5 + x_m / beam_length_m); }
  double position(double volts_V) const { return (volts_V / Vcc_V - 0.5) * beam_length_m; }
  // The wire runs the beam's whole length, so the ball is on the beam while |x| ≤ L/2 (seed 003
  // gives no beam length; 0.4 m is chosen, see presets/ballbeam.json).
  double half_length_m() const { return beam_length_m / 2.0; }
};

struct LoopParams {
  double Ts_s = 0.01;  // controller, sensor and filter period
  double duration_s = 15.0;
  double step_time_s = 1.0;         // set-point step instant
  double setpoint_m = 0.1;          // x_c after the step (0 before)
  double x0_m = 0.0;                // initial ball position, at rest
  double sigma_pos_m = 0.002;       // Gaussian position-reading noise while in contact
  double contact_loss_rate = 0.05;  // probability per sample that a contact loss begins
  int burst = 3;                    // mean contact-loss length, samples (geometric)
  std::uint64_t seed = 1;
  double V_max =
      12.0;  // motor amplifier limit |V| ≤ V_max (the PID integral stops while saturated)
  // The beam's mechanical stops |θ| ≤ θ_max (not in seed 003; assumed): the beam rests on a stop
  // (θ̇ = 0) until the motor drives it back.
  double theta_max_rad = 0.785;
  Plant plant;
  Controller ctrl;
  SensorModel sensor;
};

// The exogenous realisation shared by every closed-loop variant of one run (same seed ⇒ same
// noise, same contact losses, same spike readings).
struct Disturbances {
  std::vector<double> noise_m;  // Gaussian reading error while in contact
  std::vector<char> lost;       // 1 where the ball has lost contact with the wire
  std::vector<double> spike_m;  // the raw (impulsive) reading while contact is lost
};

// Samples of the whole run, one random stream per noise source (the table atop
// ballbeam_loop.cpp): changing the loss rate keeps the Gaussian noise.
Disturbances make_disturbances(std::size_t n, const LoopParams& p);
std::size_t loop_steps(const LoopParams& p);

// Per-step record of one run (closed loop or replay). NaN where a value does not exist.
struct LoopTrace {
  std::vector<double> t, setpoint, x_true, v_true, theta, theta_c, V;
  std::vector<double> x_meas;    // raw position reading (impulsive while contact lost)
  std::vector<double> v_raw;     // sensor voltage without the discrimination circuit (Fig. 7a)
  std::vector<double> v_sensor;  // circuit output, 0 V while contact lost (Fig. 7b)
  std::vector<double> flagged;   // 1 where the filter skipped the update (missing), else 0
  std::vector<double> x_hat, v_hat, P11, P22, innovation, S, nis, K1, K2;
  std::size_t lost_samples = 0;
  std::size_t skipped_updates = 0;
  bool diverged = false;  // the loop left ±1 km or produced NaN; later samples are NaN
  double diverged_at_s = 0.0;
  // First time the true ball position is beyond a beam end (|x| > L/2); NaN while it stays on.
  // With LoopOptions::falls the ball has fallen off there and the trace ends at the last sample
  // before (`fell`); without, the linear plant (eq. 11) carries on as if the beam were endless.
  double left_beam_at_s = std::numeric_limits<double>::quiet_NaN();
  bool fell = false;
  void resize(std::size_t n);
  // Keeps the first n samples of every per-step array.
  void truncate(std::size_t n);
};

// The first t_k with |x_k| > half_length_m (non-finite x are skipped); NaN if there is none.
double left_beam_at(const std::vector<double>& t, const std::vector<double>& x_m,
                    double half_length_m);

// The tracker's gain once settled. A time-varying KF's gain jumps after every skipped update (P̄
// grew over the missing samples) and decays back over the following updates, so the very last
// update's gain may sit on that transient. This is the gain at the end of the longest unbroken
// run of updates (the latest of equally long runs); `run` counts its updates (0: none).
struct SettledGain {
  double K1 = std::numeric_limits<double>::quiet_NaN();
  double K2 = std::numeric_limits<double>::quiet_NaN();
  std::size_t run = 0;
};
SettledGain settled_gain(const LoopTrace& tr);

struct LoopOptions {
  bool detection = true;  // the circuit flags contact losses as missing data
  bool impulsive = true;  // false: contact never lost and no reading noise (noise-free run)
  bool falls = true;      // the ball falls off a beam end and the run stops there
};

// The largest beam angle of the small-angle model ẍ = a3 θ (sin θ within 1 % of θ); beyond it
// the run warns.
inline constexpr double kSmallAngleRad = 0.25;

// Simulates the loop: at each sample read the sensor, run the tracker, compute V from the
// estimate, hold V over [t_k, t_k+1] and integrate the plant (RK4, ≤ 1 ms substeps).
LoopTrace run_closed_loop(const LoopParams& p, const BallTracker& tracker, const Disturbances& d,
                          const LoopOptions& opt, const RunControl& control = {});

// Replays the tracker over recorded data: y = x_meas (NaN = missing), flagged where v_sensor is
// exactly 0 V when `detection`, u^c = a3 θ when θ is logged (else 0).
LoopTrace replay(const std::vector<double>& t, const std::vector<double>& x_meas,
                 const std::vector<double>* v_sensor, const std::vector<double>* theta,
                 const BallTracker& tracker, bool detection, double a3,
                 const RunControl& control = {});

// The columns of a simulated log: t, x_meas, v_sensor, v_raw, theta, setpoint, truth, v_truth.
Dataset to_dataset(const LoopTrace& tr, const std::string& source);

}  // namespace kfw::ballbeam
