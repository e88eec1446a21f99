#pragma once
// The config vocabulary of common/ as sph names: every sph config struct declares its parameters
// with them (param(...) in describe()), and scene loading reads and checks them.

#include "common/config_error.h"
#include "common/config_visitors.h"
#include "common/json_file.h"
#include "common/param_spec.h"

namespace sph {

using common::apply_overrides;
using common::ConfigError;
using common::DocTable;
using common::JsonReader;
using common::JsonWriter;
using common::load_json_file;
using common::param;
using common::ParamSpec;
using common::shortest_decimal;

}  // namespace sph
