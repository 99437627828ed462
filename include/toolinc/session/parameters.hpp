// Every numeric parameter of crop-cloud, once (toolinc/core/parameter.hpp). The crop box and the
// switches (image-mask, flood) are not numbers and are declared beside the table.
#pragma once

#include <vector>

#include "toolinc/core/parameter.hpp"
#include "toolinc/session/crop.hpp"

namespace toolinc {

const std::vector<Parameter<CropConfig>>& crop_parameters();

}  // namespace toolinc
