"""hapsim.parse_trials_csv on the server's CSV format (server/classroom/src/trial_book.cpp)."""
import unittest

import hapsim

HEADER = ("session,trainee,scene,trial,end,duration_s,time_to_contact_s,peak_force_N,max_depth_mm,target_depth_mm,"
          "depth_error_mm,layers_pierced,punctures,peak_force_by_layer_N,incisions,incision_length_mm,"
          "line_deviation_max_mm,line_deviation_mean_mm,score\n")


class TrialsCsv(unittest.TestCase):
    def test_numbers_blanks_layers_and_quoted_fields(self) -> None:
        rows = hapsim.parse_trials_csv(
            HEADER
            + "t1,trainee1,acupuncture,0,reset,8.001,1.234,1.4555,12.000,10.000,2.000,skin+fat,6,"
              "skin=0.9948;fat=0.2010;muscle=1.4555,0,0.000,,,6.79\n"
            + 't2,"Li, Wei",cutting,1,running,2.500,,0.0000,0.000,,,,0,,2,19.512,0.410,0.120,\n')
        self.assertEqual(len(rows), 2)
        t1, t2 = rows
        self.assertEqual((t1.session, t1.trial, t1.end, t1.punctures), ("t1", 0, "reset", 6))
        self.assertAlmostEqual(t1.depth_error_mm, 2.0)
        self.assertEqual(t1.layers_pierced, ("skin", "fat"))
        self.assertEqual(t1.peak_force_by_layer_N, {"skin": 0.9948, "fat": 0.2010, "muscle": 1.4555})
        self.assertAlmostEqual(t1.score, 6.79)
        self.assertIsNone(t1.line_deviation_max_mm)
        self.assertEqual(t2.trainee, "Li, Wei")
        self.assertIsNone(t2.time_to_contact_s)
        self.assertIsNone(t2.target_depth_mm)
        self.assertEqual(t2.layers_pierced, ())
        self.assertEqual(t2.peak_force_by_layer_N, {})
        self.assertEqual((t2.incisions, t2.incision_length_mm, t2.line_deviation_mean_mm), (2, 19.512, 0.12))
        self.assertIsNone(t2.score)

    def test_columns_are_the_csv_header_in_order(self) -> None:
        self.assertEqual(hapsim.TrialRow.columns(), HEADER.strip().split(","))

    def test_header_only_and_missing_column(self) -> None:
        self.assertEqual(hapsim.parse_trials_csv(HEADER), [])
        with self.assertRaises(hapsim.ProtocolError):
            hapsim.parse_trials_csv("session,trainee\nt1,x\n")


if __name__ == "__main__":
    unittest.main()
