"""Real ROS map_server maps (../shared/data): the Willow Garage map and the AWS RoboMaker small house import and
export with identical YAML values and identical pixels (PGM, PNG and raw), and the occupancy the server derives
follows map_server's trinary rules."""

import unittest

import harness

MAPS = {
    "willow": ("willow_map", "willow-2010-02-18-0.10"),
    "aws_house": ("aws_small_house/maps/turtlebot3_waffle_pi", "map"),
}


def read(*parts):
    with open(harness.shared_data(*parts), "rb") as f:
        return f.read()


class RealMapsTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = harness.Server(None)
        cls.c = cls.server.client
        cls.c.create_map("real")

    @classmethod
    def tearDownClass(cls):
        cls.server.close()

    def check(self, name):
        folder, stem = MAPS[name]
        yaml_in, pgm_in = read(folder, stem + ".yaml"), read(folder, stem + ".pgm")
        values_in = harness.parse_map_yaml(yaml_in)
        self.assertEqual(values_in["image"], stem + ".pgm")
        w, h, maxval, pixels = harness.parse_pgm(pgm_in)
        self.assertEqual(maxval, 255)
        self.assertEqual(len(pixels), w * h)
        c = self.c

        info = c.import_occupancy("real", name, yaml_in, pgm_in)
        self.assertEqual((info["geometry"]["width_cells"], info["geometry"]["height_cells"]), (w, h))
        self.assertEqual(info["geometry"]["resolution_m"], values_in["resolution"])
        self.assertEqual(info["geometry"]["origin"], values_in["origin"])

        values_out = harness.parse_map_yaml(c.get_layer("real", name, "yaml"))
        self.assertEqual(values_out.pop("image"), name + ".pgm")
        values_in.pop("image")
        self.assertEqual(values_out, values_in)

        ow, oh, omax, out_pixels = harness.parse_pgm(c.get_layer("real", name, "pgm"))
        self.assertEqual((ow, oh, omax), (w, h, 255))
        self.assertTrue(out_pixels == pixels, "exported PGM pixels differ from %s.pgm" % stem)
        pw, ph, png_pixels = harness.decode_png_grey(c.get_layer("real", name, "png"))
        self.assertEqual((pw, ph), (w, h))
        self.assertTrue(png_pixels == pixels, "exported PNG pixels differ from %s.pgm" % stem)
        self.assertTrue(c.get_layer("real", name, "raw") == pixels, "raw export differs from %s.pgm" % stem)

        # map_server trinary interpretation (negate 0): p = (255 - v) / 255.
        occupied = sum(1 for v in pixels if (255 - v) / 255.0 > values_in["occupied_thresh"])
        free = sum(1 for v in pixels if (255 - v) / 255.0 < values_in["free_thresh"])
        stats = c.get_layer("real", name, statistics=True)["statistics"]
        self.assertEqual(stats, {"occupied_cells": occupied, "free_cells": free,
                                 "unknown_cells": w * h - occupied - free})

        # The PNG export imports back to the same layer.
        png_name = name + "-from-png"
        c.import_occupancy("real", png_name, c.get_layer("real", name, "yaml"), c.get_layer("real", name, "png"))
        self.assertTrue(c.get_layer("real", png_name, "pgm") == c.get_layer("real", name, "pgm"))

    def test_willow_garage_map(self):
        self.check("willow")

    def test_aws_small_house_map(self):
        self.check("aws_house")


if __name__ == "__main__":
    unittest.main()
