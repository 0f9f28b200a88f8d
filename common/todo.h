// For starter-kit stubs: prints "TODO: <what>" on stderr the first time each
// unimplemented function is reached, so a student's renderer keeps running
// and says what is missing.
#pragma once

namespace pt {

void todo_once(const char* what);

}  // namespace pt
