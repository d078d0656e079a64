// The knob table (include/masq/knobs.h) as `masq info --env` prints it: as text, with
// each variable's current value, or as the Markdown of docs/knobs.md.
#pragma once
#include <string>

namespace masq::cli {

// One block per knob: its name and current value ("(unset)", or the value quoted), its
// type and default, then its meaning and readers wrapped to 100 columns; a value its
// readers would refuse adds a "bad:" line with their error.
std::string knob_table_text();

// docs/knobs.md: the same rows without the current values, so the page does not depend
// on the environment it is generated in.
std::string knob_table_markdown();

} // namespace masq::cli
