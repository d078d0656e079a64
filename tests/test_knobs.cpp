// The knob table (include/masq/knobs.h): its rows are well formed, and every accessor
// gives the one error for a bad value, naming the variable, its value and what is
// expected. tests/knob_docs.sh checks `masq info --env` and docs/knobs.md against it.
#include "host/device_choice.h"
#include "host/limit_knob.h"
#include "masq/error.h"
#include "masq/knobs.h"
#include <gtest/gtest.h>
#include <set>
#include <string>
#include "tests/test_env.h"

namespace {

using namespace masq;
using test::ScopedEnv;

// The message of the Error `f` throws, or "" when it throws none.
template <class F>
std::string error_of(F f) {
  try {
    f();
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

TEST(Knobs, RowsAreWellFormed) {
  std::set<std::string> names;
  for (const KnobRow& row : knob_rows) {
    SCOPED_TRACE(row.name);
    EXPECT_EQ(std::string(row.name).rfind("MASQ_", 0), 0u);
    EXPECT_TRUE(names.insert(row.name).second) << "a second row named " << row.name;
    EXPECT_EQ(&knob_row(row.knob), &row);
    EXPECT_NE(std::string(row.default_text), "");
    EXPECT_NE(std::string(row.meaning), "");
    EXPECT_NE(std::string(row.readers), "");
    EXPECT_NE(std::string(row.meaning).back(), '.') << "the table adds the period";
    const bool choice = row.type == KnobType::Choice || row.type == KnobType::Flag;
    EXPECT_EQ(row.choices != nullptr, choice);
    if (row.type == KnobType::Flag) {
      EXPECT_STREQ(row.choices, "0|1");
    }
    if (row.type == KnobType::Integer) {
      EXPECT_LE(row.min, row.max);
    }
    if (choice) {
      // Unset, a choice knob reads as its default, which must be one of its choices.
      ScopedEnv unset(row.name, "");
      EXPECT_EQ(knob_choice(row.knob), row.default_text);
    }
  }
}

TEST(Knobs, DeviceSelectorsAreRows) {
  for (const DeviceApiRow& api : device_api_rows) {
    SCOPED_TRACE(api.name);
    EXPECT_EQ(knob_row(api.knob).type, KnobType::Device);
    ScopedEnv sel(knob_name(api.knob), "7");
    const DeviceSelector s = device_selector(api.value);
    EXPECT_EQ(s.value, "7");
    EXPECT_EQ(s.source, knob_name(api.knob));
  }
}

TEST(Knobs, IntegersAreDigitsInRange) {
  ScopedEnv wait("MASQ_VK_WAIT_SECONDS", "");
  EXPECT_EQ(knob_integer(Knob::VkWaitSeconds), std::nullopt);
  for (const char* ok : {"1", "007", "18446744073709551615"}) {
    ScopedEnv v("MASQ_VK_WAIT_SECONDS", ok);
    EXPECT_EQ(knob_integer(Knob::VkWaitSeconds), std::stoull(ok)) << ok;
  }
  for (const char* bad : {"soon", "12kB", "-1", "+3", " 8", "8 ", "0", "18446744073709551616", "1e3"}) {
    ScopedEnv v("MASQ_VK_WAIT_SECONDS", bad);
    EXPECT_EQ(error_of([] { knob_integer(Knob::VkWaitSeconds, "vulkan"); }),
              "vulkan: MASQ_VK_WAIT_SECONDS='" + std::string(bad) + "' is not a positive integer");
  }
  ScopedEnv diagnose("MASQ_DIAGNOSE", "0");
  EXPECT_EQ(knob_integer(Knob::Diagnose), 0u);
  ScopedEnv many("MASQ_DIAGNOSE", "1000001");
  EXPECT_EQ(error_of([] { knob_integer(Knob::Diagnose); }),
            "MASQ_DIAGNOSE='1000001' is not an integer from 0 to 1000000");
}

TEST(Knobs, ChoicesAndFlags) {
  {
    ScopedEnv v("MASQ_STEP_CHECK", "off");
    EXPECT_EQ(knob_choice(Knob::StepCheck), "off");
    EXPECT_FALSE(choice_knob("", Knob::StepCheck, "on"));
  }
  {
    ScopedEnv v("MASQ_STEP_CHECK", "maybe");
    EXPECT_EQ(error_of([] { knob_choice(Knob::StepCheck); }), "MASQ_STEP_CHECK='maybe' is not 'on' or 'off'");
  }
  {
    ScopedEnv v("MASQ_VK_VALIDATION", "yes");
    EXPECT_EQ(error_of([] { knob_choice(Knob::VkValidation, "vulkan"); }),
              "vulkan: MASQ_VK_VALIDATION='yes' is not '0', '1' or 'sync'");
  }
  for (const auto& [text, on] : {std::pair{"1", true}, std::pair{"0", false}, std::pair{"", false}}) {
    ScopedEnv v("MASQ_VK_FORCE_STAGING", text);
    EXPECT_EQ(knob_flag(Knob::VkForceStaging), on) << text;
  }
  ScopedEnv v("MASQ_VK_FORCE_STAGING", "on");
  EXPECT_EQ(error_of([] { knob_flag(Knob::VkForceStaging); }), "MASQ_VK_FORCE_STAGING='on' is not '0' or '1'");
  EXPECT_EQ(knob_problem(Knob::VkForceStaging), "MASQ_VK_FORCE_STAGING='on' is not '0' or '1'");
}

TEST(Knobs, TextKeepsSetAndEmptyApart) {
  {
    ScopedEnv v("MASQ_CACHE_DIR", "");
    EXPECT_EQ(knob_text(Knob::CacheDir), std::string());
  }
  ScopedEnv restore("MASQ_CACHE_DIR", "");
  ::unsetenv("MASQ_CACHE_DIR");
  EXPECT_EQ(knob_text(Knob::CacheDir), std::nullopt);
  EXPECT_EQ(knob_problem(Knob::CacheDir), "");
}

TEST(Knobs, LoweredLimitTakesTheSmaller) {
  ScopedEnv v("MASQ_RQ_MAX_INSTANCES", "");
  EXPECT_EQ(lowered_limit("rayquery", 100, Knob::RqMaxInstances), 100u);
  ScopedEnv low("MASQ_RQ_MAX_INSTANCES", "40");
  EXPECT_EQ(lowered_limit("rayquery", 100, Knob::RqMaxInstances), 40u);
  ScopedEnv high("MASQ_RQ_MAX_INSTANCES", "400");
  EXPECT_EQ(lowered_limit("rayquery", 100, Knob::RqMaxInstances), 100u);
}

TEST(Knobs, AnAccessorOfAnotherTypeIsAnError) {
  EXPECT_NE(error_of([] { knob_integer(Knob::Data); }).find("knob_integer(MASQ_DATA)"), std::string::npos);
  EXPECT_NE(error_of([] { knob_flag(Knob::StepCheck); }).find("knob_flag(MASQ_STEP_CHECK)"), std::string::npos);
}

} // namespace
