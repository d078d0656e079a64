#pragma once
// masq::Error (and BackendUnavailable) are defined once in the public header so the
// library's users catch the very types its internals throw.
#include "masq/error.h"
