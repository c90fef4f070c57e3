// Deliberately wrong: a lower module including a higher one (check-layout must report it).
#pragma once
#include "polydem/high/high.h"
