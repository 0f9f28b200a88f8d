// The viewer's worker process: every render and every BVH build runs here,
// in a child of the server started from the same binary, so that a crash
// in a part's code ends the child, not the server.
//
// Protocol on the worker's standard output (the worker moves the
// program's own stdout to stderr first, so stray prints cannot break it):
//   FRAME <json>\n<bytes>   one pass of a render (progressive.h); the json gives "bytes",
//                           the payload is width*height pixels of
//                           {float r, g, b; uint32 samples; float tests per ray},
//                           row 0 at the bottom
//   BVH <json>\n<bytes>     a BVH (see write_bvh in worker.cpp)
//   DONE\n                  finished
// On standard error: the part's own lines (TODO: implement ...), and on a
// fault "CRASH <signal>" followed by a backtrace, or "ERROR <message>".
#pragma once

namespace pt::viewer {

// argv[1] is "--worker", argv[2] the job ("render" or "bvh"), the rest are
// pathtracer flags and the scene. Returns the exit status.
int worker_main(int argc, char** argv);

}  // namespace pt::viewer
