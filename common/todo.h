// For starter-kit stubs. PT_TODO(part) prints, on stderr and only the first
// time that line is reached,
//   TODO: implement Part <part>: <function> (<file>)
// naming the function it is written in and its source file from the
// repository's root, so that a student's renderer keeps running and says
// what is missing. The grader reads these lines (the part number says which
// cases a missing function dooms); keep the format.
// PT_TODO_AS(part, name, note) gives the name itself, for a member function
// or a constructor, whose __func__ ("intersect", "build") is not the name a
// student looks for, and adds "; <note>" when the note is not empty.
#pragma once
#include <string>

namespace pt {

// "Part <part>: <name> (<file>)", plus "; <note>" when note is not empty.
// `file` is made relative to the repository's root (the build's source
// folder, or else from its last "stages/" folder on).
std::string todo_message(int part, const char* name, const char* file, const char* note = "");

// Prints "TODO: implement " + todo_message(...) on stderr. Returns true, to
// initialise the static that makes PT_TODO print once.
bool todo_print(int part, const char* name, const char* file, const char* note = "");

// Called every time a stub is reached: tells the path inspector's recorder,
// when one is recording on this thread (a null check otherwise).
void todo_reached(int part, const char* name, const char* file, const char* note = "");

// Prints "TODO: implement <what>" the first time each text is passed.
void todo_once(const char* what);

// For a stub's stand-in: marks parameters it does not need as used.
template <class... T>
inline void unused(const T&...) {}

}  // namespace pt

#define PT_TODO(part) PT_TODO_AS(part, __func__, "")

#define PT_TODO_AS(part, name, note)                                                    \
  do {                                                                                  \
    static const bool pt_todo_printed = ::pt::todo_print(part, name, __FILE__, note);   \
    (void)pt_todo_printed;                                                              \
    ::pt::todo_reached(part, name, __FILE__, note);                                     \
  } while (0)
