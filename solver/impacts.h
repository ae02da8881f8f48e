#pragma once
/// Impacts: at an event, every open contact that approaches with its gap closed takes an impulse,
/// the fastest first, until none approaches. The maths is at the top of impacts.cc.

#include "core/compile/compiled_model.h"
#include "solver/integration_state.h"

namespace momenta {

constexpr double kGapBand = 1e-10;       ///< gaps within this [m] count as closed
constexpr double kVelocityBand = 1e-12;  ///< approach speeds below this [m/s] are none

/// Resolves the impacts at t on run->y, run->y' (the left limit), one contact at a time: each
/// jump of the states is added to run->y, a contact that comes to rest is closed (its contact
/// mode set), and run->stats counts the impacts.
void ResolveImpacts(const CompiledModel& model, ModelState* state, IntegrationState* run, double t);

}  // namespace momenta
