// Deliberately wrong: includes module low without DEPENDS polydem::low in its CMakeLists.txt.
#pragma once
#include "polydem/low/low.h"
