// Dominant frequency of each cell's V: the frequency of the largest peak of
// its power spectrum within a band (Skanes et al. 1998, Circulation 98:1236,
// who map AF by the dominant frequency of each site's optical signal).
//
// The spectrum is a direct DFT of the uniformly sampled series, mean
// removed and Hann-windowed, evaluated only at the bins k / T inside
// [f_min_hz, f_max_hz] (T = samples x interval): the band of AF (a few Hz to
// about 20 Hz) holds few bins, so this costs samples x cells x bins without
// an FFT library. The resolution is 1 / T: a longer record resolves more
// finely.
#pragma once

#include <cstddef>
#include <vector>

namespace fibrodem {

struct DominantFrequencies {
  std::vector<double> per_cell_hz;  // NaN for a cell left out (see below)
  double resolution_hz = 0;         // 1 / T
};

struct FrequencyBand {
  double f_min_hz = 0, f_max_hz = 0;
};

// frames: `samples` frames of `cells` values each (frame-major), every_ms
// apart. Cells whose V spans less than min_range_mV over the record (never
// excited) are left out (NaN); so are all when fewer than 4 samples, or no
// bin, fall in the band.
DominantFrequencies dominant_frequencies(const std::vector<float>& frames, std::size_t cells, std::size_t samples,
                                         double every_ms, double f_min_hz, double f_max_hz,
                                         double min_range_mV = 20.0);

// The same in each of several bands, from one spectrum over the bins of
// them all (a band inside another costs no bin more); one result per band.
std::vector<DominantFrequencies> dominant_frequencies(const std::vector<float>& frames, std::size_t cells,
                                                      std::size_t samples, double every_ms,
                                                      const std::vector<FrequencyBand>& bands,
                                                      double min_range_mV = 20.0);

}  // namespace fibrodem
