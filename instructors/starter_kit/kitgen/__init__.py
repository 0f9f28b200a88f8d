"""The starter-kit generator's parts (make_starter_kit.py is the command):

    base      KitError, what a C++ source is
    markers   stripping solution regions (keeping them for a part given solved);
              hints in emptied helper namespaces
    cpp_text  C++ text with comments, literals and preprocessor lines blanked
    scanner   the namespace-level definitions of a C++ file
    given     the parts' "## Given code" tables and the check against them
    checks    references to left-out files, links, leaks, TODO parts
    solved    parts given solved (--solved-parts): their files, the notes
    tree      the files of the kit, built and checked in memory
"""
