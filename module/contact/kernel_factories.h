// Factory functions of the contact kernels, one per kernel file (see kernel_list.inc).
#pragma once

#include <memory>

#include "polydem/contact/contact.h"

namespace polydem::contact {
std::unique_ptr<Kernel> makeGjkEpa(const KernelParams& params);     // gjk_epa.cpp
std::unique_ptr<Kernel> makeGjkEpaIpm(const KernelParams& params);  // gjk_epa.cpp
std::unique_ptr<Kernel> makeFcp(const KernelParams& params);        // fcp.cpp
std::unique_ptr<Kernel> makeFcpIpm(const KernelParams& params);     // fcp.cpp
std::unique_ptr<Kernel> makeLp(const KernelParams& params);         // lp.cpp
std::unique_ptr<Kernel> makeDistancePotentialKernel(const KernelParams& params);
std::unique_ptr<Kernel> makeFdemKernel(const KernelParams& params);
}  // namespace polydem::contact
