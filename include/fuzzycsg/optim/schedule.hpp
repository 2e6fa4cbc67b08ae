#pragma once
// Schedules of a value over the steps of a descent (learning rates, temperatures, sharpness).
// Each engine decides what fraction of its run a step is (fit counts steps of `iters`, trace's
// refinement the steps between its first and its last) and passes its own option values.

namespace fuzzycsg::optim {

// Cosine annealing (Loshchilov & Hutter 2017, without restarts): lr at f = 0 down to
// lr * end_fraction at f = 1; f is clamped to [0, 1].
double cosine_lr(double lr, double end_fraction, double f);

// start (end / start)^f: start at f = 0, end at f = 1, the same factor for each equal step of
// f. start and end > 0.
double geometric(double start, double end, double f);

// The geometric ramp from start to end over the first `ramp_steps` steps (which need not be a
// whole number), then end; end throughout when ramp_steps <= 0.
double geometric_ramp(double start, double end, double ramp_steps, long step);

}  // namespace fuzzycsg::optim
