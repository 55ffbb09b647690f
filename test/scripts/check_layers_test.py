#!/usr/bin/env python3
"""Tests of scripts/check_layers on small trees built here: a clean tree passes, and an upward
include, a ROS header in a core layer, a source outside the layer folders and a header whose
functions have no source each fail with a message naming the file, the line and the rule; so do
a test or benchmark including a layer its declaration in CMakeLists.txt does not name (directly
or through a test/support/ or bench/ header) and a relative include leaving its folder."""
import os
import subprocess
import sys
import tempfile
import unittest

CHECKER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts",
                       "check_layers")
TABLE = """# test table
common:
geometry:
data: geometry common
models: data
ros: models
bag: ros
cli: models
"""
CMAKE = """# odometry_calibration_test(LAYER NAME [USES layer...]) is not a declaration in a comment
function(odometry_calibration_test layer name)
endfunction()
foreach(data_test encoder keyframes)
  odometry_calibration_test(data ${data_test} USES models)
endforeach()
odometry_calibration_test(geometry se2)
odometry_calibration_bench(bench_model bench/model_bench.cpp models)
odometry_calibration_bench(bench_node bench/node_bench.cpp ros)
"""


def write(root, path, text):
    full = os.path.join(root, path)
    os.makedirs(os.path.dirname(full), exist_ok=True)
    with open(full, "w") as f:
        f.write(text)


def clean_tree(root):
    write(root, "cmake/layers.txt", TABLE)
    write(root, "msg/Report.msg", "string text\n")
    write(root, "include/odometry_calibration/geometry/se2.h",
          "#pragma once\nnamespace oc {\ninline double half(double x) { return x / 2; }\n}\n")
    write(root, "include/odometry_calibration/data/encoder.h",
          '#pragma once\n#include "odometry_calibration/geometry/se2.h"\n'
          "namespace oc {\ndouble ticks(int n);\nstruct Decoder\n{\n  Decoder() = default;\n"
          "  double decode(int n) const;\n};\n}\n")
    write(root, "src/data/encoder.cpp", '#include "odometry_calibration/data/encoder.h"\n')
    write(root, "include/odometry_calibration/models/model.h",
          '#pragma once\n#include "odometry_calibration/data/encoder.h"\n'
          "namespace oc {\nclass Model\n{\npublic:\n  virtual ~Model() = default;\n"
          "  virtual double fit() = 0;\n};\n}\n")
    write(root, "include/odometry_calibration/ros/node.h",
          '#pragma once\n#include <ros/ros.h>\n#include "odometry_calibration/Report.h"\n'
          '#include "odometry_calibration/models/model.h"\nvoid run();\n')
    write(root, "src/ros/node.cpp", '#include "odometry_calibration/ros/node.h"\n')
    write(root, "src/tools/tool_main.cpp", "#include <sensor_msgs/LaserScan.h>\n")
    write(root, "test/ros/node_test.cpp", "#include <ros/ros.h>\n")
    write(root, "test/data/encoder_test.cpp",
          '#include "odometry_calibration/models/model.h"\n#include "support/fixture.h"\n')
    write(root, "test/data/keyframes_test.cpp", '#include "odometry_calibration/models/model.h"\n')
    write(root, "test/support/fixture.h", '#pragma once\n#include "odometry_calibration/data/'
          'encoder.h"\n')
    write(root, "test/geometry/se2_test.cpp",
          '#include "odometry_calibration/geometry/se2.h"\n#include "support/files.h"\n')
    write(root, "test/support/files.h", "#pragma once\n#include <string>\n")
    write(root, "bench/model_bench.cpp", '#include "odometry_calibration/models/model.h"\n'
          '#include "bench_helper.h"\n#include "support/fixture.h"\n')
    write(root, "bench/bench_helper.h", '#pragma once\n#include "odometry_calibration/data/'
          'encoder.h"\n')
    write(root, "bench/node_bench.cpp", '#include <ros/ros.h>\n#include "odometry_calibration/'
          'ros/node.h"\n')
    write(root, "CMakeLists.txt", CMAKE)


def run(root):
    result = subprocess.run([sys.executable, CHECKER, root], stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    return result.returncode, result.stdout


class CheckLayersTest(unittest.TestCase):
    def setUp(self):
        self.directory = tempfile.TemporaryDirectory()
        self.root = self.directory.name
        clean_tree(self.root)

    def tearDown(self):
        self.directory.cleanup()

    def test_clean_tree_passes(self):
        code, output = run(self.root)
        self.assertEqual(code, 0, output)

    def test_upward_include_fails(self):
        write(self.root, "src/data/encoder.cpp",
              '#include "odometry_calibration/data/encoder.h"\n\n'
              '#include "odometry_calibration/models/model.h"\n')
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("src/data/encoder.cpp:3: data may not include models/ (cmake/layers.txt)",
                      output)

    def test_ros_include_in_core_layer_fails(self):
        write(self.root, "include/odometry_calibration/geometry/se2.h",
              "#pragma once\n#include <ros/ros.h>\n")
        write(self.root, "src/data/encoder.cpp",
              '#include "odometry_calibration/data/encoder.h"\n#include "odometry_calibration/'
              'Report.h"\n#include <geometry_msgs/Pose2D.h>\n')
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("include/odometry_calibration/geometry/se2.h:2: geometry may not include "
                      "ROS header ros/ros.h", output)
        self.assertIn("src/data/encoder.cpp:2: data may not include ROS header "
                      "odometry_calibration/Report.h", output)
        self.assertIn("src/data/encoder.cpp:3: data may not include ROS header "
                      "geometry_msgs/Pose2D.h", output)

    def test_ros_headers_only_in_ros_and_the_layers_using_it(self):
        # bag uses ros: a ROS layer; cli, listed after ros but not using it, is core.
        write(self.root, "include/odometry_calibration/bag/reader.h",
              '#pragma once\n#include <rosbag/bag.h>\n#include "odometry_calibration/ros/'
              'node.h"\nvoid read();\n')
        write(self.root, "src/bag/reader.cpp", '#include "odometry_calibration/bag/reader.h"\n')
        write(self.root, "src/cli/tool.cpp", "#include <ros/time.h>\n")
        write(self.root, "include/odometry_calibration/cli/tool.h", "#pragma once\nvoid tool();\n")
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("src/cli/tool.cpp:1: cli may not include ROS header ros/time.h (only the "
                      "ROS layers: bag ros; the mains)", output)
        self.assertNotIn("bag/reader", output)

    def test_ros_include_in_core_test_fails(self):
        write(self.root, "test/data/encoder_test.cpp", "#include <ros/time.h>\n")
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("test/data/encoder_test.cpp:1:", output)

    def test_source_outside_layers_fails(self):
        write(self.root, "src/core/encoder.cpp", "int x;\n")
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("src/core/encoder.cpp:1: not in a layer folder", output)

    def test_header_without_source_fails(self):
        os.remove(os.path.join(self.root, "src/data/encoder.cpp"))
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("include/odometry_calibration/data/encoder.h:1: declares functions but "
                      "src/data/ has no encoder.cpp", output)

    def test_source_named_after_no_header_fails(self):
        write(self.root, "src/data/keyframes.cpp", "int y;\n")
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("src/data/keyframes.cpp:1: implements no header of its layer", output)

    def test_test_including_an_undeclared_layer_fails(self):
        write(self.root, "CMakeLists.txt", CMAKE.replace("${data_test} USES models",
                                                         "${data_test}"))
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("test/data/encoder_test.cpp:1: the data test may not include models/ "
                      "(its layer, the layers below and its USES in CMakeLists.txt)", output)
        self.assertIn("test/data/keyframes_test.cpp:1: the data test may not include models/",
                      output)

    def test_test_including_a_layer_through_a_support_header_fails(self):
        write(self.root, "test/support/files.h",
              '#pragma once\n#include "odometry_calibration/data/encoder.h"\n')
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("test/geometry/se2_test.cpp:2: the geometry test may not include data/ "
                      "(through test/support/files.h)", output)

    def test_undeclared_test_uses_its_layer_and_those_below_only(self):
        write(self.root, "test/geometry/pose_test.cpp",
              '#include "odometry_calibration/geometry/se2.h"\n'
              '#include "odometry_calibration/data/encoder.h"\n')
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("test/geometry/pose_test.cpp:2: the geometry test may not include data/",
                      output)

    def test_benchmark_including_an_undeclared_layer_fails(self):
        write(self.root, "bench/bench_helper.h",
              '#pragma once\n#include "odometry_calibration/ros/node.h"\n')
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("bench/model_bench.cpp:2: this benchmark may not include ros/ (through "
                      "bench/bench_helper.h)", output)

    def test_ros_header_in_a_benchmark_not_naming_ros_fails(self):
        write(self.root, "bench/model_bench.cpp", "#include <sensor_msgs/LaserScan.h>\n")
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("bench/model_bench.cpp:1: this benchmark may not include ROS header "
                      "sensor_msgs/LaserScan.h", output)

    def test_undeclared_benchmark_fails(self):
        write(self.root, "bench/scan_bench.cpp", "int main() { return 0; }\n")
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn("bench/scan_bench.cpp:1: declared by no odometry_calibration_bench", output)

    def test_relative_include_leaving_its_layer_fails(self):
        write(self.root, "include/odometry_calibration/data/encoder.h",
              '#pragma once\n#include "../models/model.h"\n'
              "namespace oc {\ndouble ticks(int n);\n}\n")
        write(self.root, "src/data/encoder.cpp",
              '#include "../../include/odometry_calibration/data/encoder.h"\n')
        write(self.root, "test/data/encoder_test.cpp", '#include "../support/fixture.h"\n')
        code, output = run(self.root)
        self.assertEqual(code, 1, output)
        self.assertIn('include/odometry_calibration/data/encoder.h:2: relative include '
                      '"../models/model.h" leaves include/odometry_calibration/data/', output)
        self.assertIn('src/data/encoder.cpp:1: relative include "../../include/odometry_'
                      'calibration/data/encoder.h" leaves src/data/', output)
        self.assertIn('test/data/encoder_test.cpp:1: relative include "../support/fixture.h" '
                      'leaves test/data/', output)

    def test_relative_include_within_its_folder_passes(self):
        write(self.root, "include/odometry_calibration/data/ticks.h", "#pragma once\n")
        write(self.root, "include/odometry_calibration/data/encoder.h",
              '#pragma once\n#include "ticks.h"\n#include "../data/ticks.h"\n')
        code, output = run(self.root)
        self.assertEqual(code, 0, output)

    def test_layer_using_undefined_layer_is_a_table_error(self):
        write(self.root, "cmake/layers.txt", "common: geometry\ngeometry:\n")
        code, output = run(self.root)
        self.assertEqual(code, 2, output)

    def test_repository_tree_passes(self):
        code, output = run(os.path.join(os.path.dirname(CHECKER), ".."))
        self.assertEqual(code, 0, output)


if __name__ == "__main__":
    unittest.main()
