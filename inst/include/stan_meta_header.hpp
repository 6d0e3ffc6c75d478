// Included by every Stan model of the package (rstantools), inside the
// model's namespace, before the model class.
#include "normal_two_kernels.hpp"
#include "normal_basis.hpp"
