#!/usr/bin/env python3
"""Unit test of check_structure.py on tiny fixture trees: what must be flagged is, what must not
be is not (so the check cannot silently pass everything). Python 3 standard library only.

Usage: tools/scripts/check_structure_test.py (CTest: Structure.check_structure_selftest)
"""

import io
import os
import sys
import tempfile
import textwrap
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_structure as cs  # noqa: E402


def function_lines(body_lines):
    """A function whose declaration-to-closing-brace length is body_lines + 3."""
    return "int F(int a) {\n" + "  a += 1;\n" * body_lines + "  return a;\n}\n"


def lengths(source):
    return [(name, end - start + 1) for start, end, name in
            cs.functions(cs.blank_code(textwrap.dedent(source)))]


class BlankCodeTest(unittest.TestCase):
    def test_literals_and_comments_lose_their_braces_but_keep_lines(self):
        src = textwrap.dedent('''\
            // a { comment
            /* and { another
               } */
            const char* s = "{ \\" }";
            char c = '{';
            char d = '\\'';
            auto r = R"x(a ) " { )x";
            int big = 1'000'000;
            #define OPEN {
            #if X \\
              {
            #endif
            ''')
        code = cs.blank_code(src)
        self.assertEqual(code.count("\n"), src.count("\n"))
        self.assertNotIn("{", code)
        self.assertNotIn("}", code)
        self.assertIn("int big = 1'000'000;", code)


class FunctionsTest(unittest.TestCase):
    def test_length_counts_from_declaration_to_closing_brace(self):
        self.assertEqual(lengths(function_lines(58)), [("F", 61)])

    def test_braces_in_literals_do_not_end_a_function(self):
        src = '''\
            std::string F() {
              std::string a = "}}}";
              char b = '}';
              auto c = R"(}})";
              // }
              return a;
            }
            int G() { return 1; }
            '''
        self.assertEqual(lengths(src), [("F", 7), ("G", 1)])

    def test_scopes_and_initializers_are_not_functions(self):
        src = '''\
            namespace a::b {
            enum class E { kA, kB };
            struct S {
              int x{1};
              int Get() const noexcept { return x; }
              auto Sum(int y) -> int {
                return x + y;
              }
            };
            const int kTable[] = {1, 2, 3};
            const std::vector<int> kMade = Make({1, 2});
            }  // namespace a::b
            extern "C" {
            void C(void) {}
            }
            '''
        self.assertEqual(lengths(src), [("Get", 1), ("Sum", 3), ("C", 1)])

    def test_constructor_initializer_list_braces_belong_to_the_declaration(self):
        src = '''\
            Foo::Foo(int a)
                : a_{a},
                  b_(std::vector<int>{1, 2}),
                  c_{} {
              Start();
            }
            '''
        self.assertEqual(lengths(src), [("Foo::Foo", 6)])

    def test_lambdas_count_towards_their_enclosing_function(self):
        src = '''\
            void Outer() {
              auto f = [](int x) {
                if (x) { return 1; }
                return 2;
              };
              struct Local { int M() { return 3; } };
            }
            const auto kLambda = [](int x) {
              return x;
            };
            '''
        self.assertEqual(lengths(src), [("Outer", 7), ("kLambda", 3)])

    def test_control_statements_at_class_scope_are_not_confused(self):
        src = '''\
            template <typename T>
            T Max(T a, T b) {
              if (a > b) {
                return a;
              }
              return b;
            }
            bool operator==(const A& x, const A& y) { return x.v == y.v; }
            '''
        self.assertEqual(lengths(src), [("Max", 7), ("operator==", 1)])


class TreeTest(unittest.TestCase):
    """A fixture tree with every kind of offence, and clean files beside them."""

    def setUp(self):
        self.tmp = tempfile.TemporaryDirectory()
        self.root = self.tmp.name
        self.saved = (cs.ALLOWED_UPWARD, cs.ALLOWED_LONG_FILES, cs.ALLOWED_LONG_FUNCTIONS)
        cs.ALLOWED_UPWARD, cs.ALLOWED_LONG_FILES, cs.ALLOWED_LONG_FUNCTIONS = [], {}, {}
        for folder in ("base", "geometry", "imaging", "mosaic", "calibration", "fleet", "io"):
            os.makedirs(os.path.join(self.root, "common", folder))
        self.write("common/base/status.h", "#pragma once\nstruct Status {};\n")
        self.write("common/tracking/CMakeLists.txt",
                   "add_library(t_tracking a.cpp)\ntarget_link_libraries(t_tracking PUBLIC "
                   "t_geometry)  # fine: down\n")
        self.write("common/geometry/CMakeLists.txt",
                   "add_library(t_geometry p.cpp)\n"
                   "# target_link_libraries(t_geometry PUBLIC t_tracking) commented out\n"
                   "target_link_libraries(t_geometry PUBLIC t_base)\n"
                   "add_executable(up_test up_test.cpp)\n"
                   "target_link_libraries(up_test PRIVATE t_tracking)  # tests may\n")
        self.write("common/base/CMakeLists.txt", "add_library(t_base INTERFACE)\n")
        self.write("common/tracking/a.cpp",
                   '#include "geometry/pose.h"\n#include "base/status.h"\n'
                   '#include <vector>\n' + function_lines(57))  # 60 lines: fine
        self.write("common/geometry/pose.h", "#pragma once\n" + "// line\n" * 398)
        self.write("common/geometry/up_test.cpp",
                   '#include "tracking/a.h"\n' + function_lines(100) + "//\n" * 400)

    def tearDown(self):
        cs.ALLOWED_UPWARD, cs.ALLOWED_LONG_FILES, cs.ALLOWED_LONG_FUNCTIONS = self.saved
        self.tmp.cleanup()

    def write(self, rel, text):
        path = os.path.join(self.root, rel)
        os.makedirs(os.path.dirname(path), exist_ok=True)
        with open(path, "w") as f:
            f.write(text)

    def run_check(self):
        out = io.StringIO()
        failures = cs.check(self.root, out=out)
        return failures, out.getvalue()

    def test_clean_tree_passes(self):
        failures, report = self.run_check()
        self.assertEqual(failures, 0, report)
        self.assertNotIn("OFFENCE", report)

    def test_upward_include_and_link_are_flagged(self):
        self.write("common/geometry/p.cpp", '#include "tracking/a.h"\nvoid P() {}\n')
        self.write("common/geometry/CMakeLists.txt",
                   "add_library(t_geometry p.cpp)\n"
                   "target_link_libraries(t_geometry PUBLIC t_base\n  PRIVATE t_tracking)\n")
        failures, report = self.run_check()
        self.assertEqual(failures, 2, report)
        self.assertIn("upward include OFFENCE: common/geometry -> common/tracking", report)
        self.assertIn("common/geometry/p.cpp:1 (tracking/a.h)", report)
        self.assertIn("upward link OFFENCE: t_geometry -> t_tracking", report)

    def test_allow_list_passes_and_stale_entries_fail(self):
        self.write("common/geometry/p.cpp", '#include "tracking/a.h"\n')
        cs.ALLOWED_UPWARD = [("include", "common/geometry", "common/tracking"),
                             ("link", "t_geometry", "t_tracking")]
        failures, report = self.run_check()
        self.assertIn("upward include allowed: common/geometry -> common/tracking", report)
        self.assertIn("STALE allow-list entry: t_geometry -> t_tracking", report)
        self.assertEqual(failures, 1, report)

    def test_unknown_folder_has_no_layer(self):
        self.write("common/newthing/x.h", "#pragma once\n")
        failures, report = self.run_check()
        self.assertEqual(failures, 1, report)
        self.assertIn("common/newthing has no layer", report)

    def test_long_file_is_flagged_test_files_are_not(self):
        self.write("common/geometry/long.h", "//\n" * 401)
        self.write("common/geometry/long_test.cpp", "//\n" * 900)
        self.write("tests/whatever.cpp", "//\n" * 900)
        failures, report = self.run_check()
        self.assertEqual(failures, 1, report)
        self.assertIn("file OFFENCE: common/geometry/long.h has 401 lines", report)

    def test_long_function_is_flagged_with_file_line_and_length(self):
        self.write("common/geometry/f.cpp", "\n\n" + function_lines(58))
        failures, report = self.run_check()
        self.assertEqual(failures, 1, report)
        self.assertIn("function OFFENCE: common/geometry/f.cpp:3 F is 61 lines", report)

    def test_allowed_long_function_may_not_grow_and_shrinks_when_fixed(self):
        self.write("common/geometry/f.cpp", function_lines(58))
        cs.ALLOWED_LONG_FUNCTIONS = {"common/geometry/f.cpp:F": [61]}
        self.assertEqual(self.run_check()[0], 0)
        self.write("common/geometry/f.cpp", function_lines(59))
        failures, report = self.run_check()
        self.assertIn("function OFFENCE: common/geometry/f.cpp:1 F is 62 lines", report)
        self.write("common/geometry/f.cpp", function_lines(10))
        failures, report = self.run_check()
        self.assertEqual(failures, 1, report)
        self.assertIn("function STALE allow-list entry: common/geometry/f.cpp:F", report)

    def test_the_real_tree_is_measured(self):
        # The check on this repository sees its files and functions (not an empty walk).
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..")
        out = io.StringIO()
        cs.ALLOWED_UPWARD, cs.ALLOWED_LONG_FILES, cs.ALLOWED_LONG_FUNCTIONS = self.saved
        cs.check(root, out=out)
        summary = out.getvalue().strip().splitlines()[-1]
        files = int(summary.split("check_structure: ")[1].split(" files")[0])
        functions = int(summary.split(" files, ")[1].split(" functions")[0])
        self.assertGreater(files, 300, summary)
        self.assertGreater(functions, 1500, summary)


if __name__ == "__main__":
    unittest.main()
