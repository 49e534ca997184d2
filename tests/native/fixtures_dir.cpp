#include "test_helpers.h"

namespace springbones::test {

const char* fixturesDir() { return SPRINGBONES_FIXTURES_DIR; }

}  // namespace springbones::test
