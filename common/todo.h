// For starter-kit stubs. PT_TODO(part, note) prints, on stderr and only the
// first time that line is reached,
//   TODO: implement Part <part>: <function> (<file>); <note>
// naming the function it is written in and its source file from the
// repository's root, and saying what the stub does meanwhile (the note),
// so that a student's renderer keeps running and says what is missing. The
// grader reads these lines (the part number says which cases a missing
// function dooms); keep the format. PT_TODO(part) has no note.
// PT_TODO_AS(part, name, note) gives the name itself, for a member function
// or a constructor, whose __func__ ("intersect", "build") is not the name a
// student looks for.
//
// Every such line in the program is also listed, whether it runs or not
// (todo_sites()): the viewer starts at the last part whose code is written.
#pragma once
#include <string>
#include <vector>

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

// A stub in this program: its part, function, file (as written by the
// compiler) and note. Each PT_TODO line puts one in the section
// "pt_todo_sites", which the linker gathers.
struct TodoSite {
  int part;
  const char* name;
  const char* file;
  const char* note;
};

// The stubs compiled into this program (none in the reference), in no
// particular order.
std::vector<TodoSite> todo_sites();

// For a stub's stand-in: marks parameters it does not need as used.
template <class... T>
inline void unused(const T&...) {}

}  // namespace pt

// PT_TODO(part) or PT_TODO(part, note).
#define PT_TODO(...) PT_TODO_PICK_(__VA_ARGS__, PT_TODO_NOTE_, PT_TODO_PART_, unused)(__VA_ARGS__)
#define PT_TODO_PICK_(a, b, name, ...) name
#define PT_TODO_PART_(part) PT_TODO_AS(part, __func__, "")
#define PT_TODO_NOTE_(part, note) PT_TODO_AS(part, __func__, note)

#define PT_TODO_AS(part, name, note)                                                                     \
  do {                                                                                                   \
    __attribute__((used, section("pt_todo_sites"))) static const ::pt::TodoSite pt_todo_site = {         \
        part, name, __FILE__, note};                                                                     \
    static const bool pt_todo_printed = ::pt::todo_print(part, name, __FILE__, note);                    \
    (void)pt_todo_printed;                                                                               \
    ::pt::todo_reached(part, name, __FILE__, note);                                                      \
  } while (0)
