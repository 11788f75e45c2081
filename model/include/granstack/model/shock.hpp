#pragma once
// What a protected object feels from the wall's force history (docs/physics.md section 7): the
// force a load cell reports through a standard channel filter, and the shock response spectrum of
// a mass mounted on the protected object. Both read the series' samples of the wall's force,
// linear between samples, as model::peak_window_impulse does, from F = 0 at the run's start.
#include <cstddef>
#include <string>
#include <vector>

namespace granstack::model {

// SAE J211-1 / ISO 6487 channel frequency classes: 60, 180, 600 and 1000.
bool is_channel_class(int cfc);
// The class's corner frequency F_H (Hz), where the phaseless filter is 3 dB down: 5/3 CFC.
double channel_corner_frequency(int cfc);
// Its design frequency f_d (Hz): 2.0775 CFC.
double channel_design_frequency(int cfc);

// The highest frequency a series sampled every `interval` s resolves for these measures: a tenth of
// its sample rate (ten samples a period; ISO 18431-4's rule for a shock response spectrum, and
// what the channel filter asks of its design frequency, beyond which the bilinear transform's
// warping is no longer small). Above it, what a measure reads is the interpolation between
// samples, not the blow.
double highest_resolved_frequency(double interval);
// Why measures reading up to `frequency` Hz (`what` names them) cannot be taken from a series
// sampled every `interval` s, or "".
std::string unresolved(const std::string& what, double frequency, double interval);

// `x`, sampled every `interval` s, through the channel filter of class `cfc` as SAE J211-1
// (appendix C) gives it: a two-pole Butterworth low-pass of design frequency 2.0775 CFC,
// prewarped for the bilinear transform, run forward and then backward in time (four poles, no
// phase shift). The signal is taken as zero before its first sample and after its last (the wall
// carries no load before the blow or after its end), padded with zeros for the filter's memory.
// A phaseless filter spreads a short blow over about 1 / f_d on both sides of it, before the
// blow began as well as after it ended (a reading taken only while the wall was loaded would
// miss a third of a 0.15 ms blow's area through CFC 1000): the result holds the filtered signal
// wherever it is above 1e-12 of its largest value, `first` the index of the first sample's time.
// Throws std::invalid_argument for a class that is not one, or samples too sparse for it (a
// design frequency above a tenth of the sample rate, where the bilinear transform's warping is no
// longer small).
struct Filtered {
  std::vector<double> values;  // every `interval` s
  std::size_t first = 0;       // values[first + k] is at the time of x[k]
};
Filtered channel_filter(const std::vector<double>& x, double interval, int cfc);
// The filter's gain at frequency f (Hz) for that sampling, in closed form:
// 1 / (1 + (tan(pi f T) / tan(pi f_d T))^4), f_d = 2.0775 CFC.
double channel_filter_gain(double f, double interval, int cfc);

// The maximax shock response spectrum at natural frequency f_n (Hz) with damping ratio zeta: the
// largest absolute acceleration of a single-degree-of-freedom oscillator whose base moves with
// acceleration `base` (m/s^2, sampled every `interval` s from one interval after t = 0, zero at
// t = 0 and linear between samples), over the samples and over its free vibration after them
// (one and a half natural periods, 256 points a period). The oscillator is integrated exactly for
// the piecewise-linear input (its state-transition matrices, Eigen's matrix exponential).
double shock_response(const std::vector<double>& base, double interval, double f_n, double zeta);
// Natural frequencies from `low` to `high` (Hz) at 12 a octave (ISO 18431-4's finest common
// spacing), both ends included.
std::vector<double> shock_response_frequencies(double low, double high);
struct ShockResponsePeak {
  double acceleration = 0.0;  // m/s^2
  double frequency = 0.0;     // Hz, where it is
};
// The spectrum's largest value over shock_response_frequencies(low, high).
ShockResponsePeak shock_response_peak(const std::vector<double>& base, double interval, double low, double high, double zeta);

}  // namespace granstack::model
