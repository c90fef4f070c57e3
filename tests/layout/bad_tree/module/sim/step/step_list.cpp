// Deliberately wrong: composes the step's operators in another order than the test tree's
// docs/architecture.md lists them, and one more (check-layout must report it).
constexpr Operator kStep[] = {
    {"derived",   Part::kForces, updateDerived},
    {"sort",      Part::kOrder,  sortParticles},
    {"integrate", Part::kMove,   integrate},
};
