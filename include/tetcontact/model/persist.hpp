// What a checkpoint holds of the data layer (model/archive.hpp): the state, the samples and the
// run's ledgers, each written and read back by the one function below.
#pragma once

#include "tetcontact/model/archive.hpp"
#include "tetcontact/model/sample.hpp"
#include "tetcontact/model/state.hpp"

namespace tc {

void persist(Archive& ar, Surface& s);
void persist(Archive& ar, ParticleMatter& pm);
/// Every array of the state, the surfaces of the run, t, τ and the step.
void persist(Archive& ar, State& st);
void persist(Archive& ar, ImpulseLedger& l);
void persist(Archive& ar, Sample& s);
void persist(Archive& ar, StepProfile& p);

}  // namespace tc
