// The checksum of the results files: a case file and summary.h5 start with a 512-byte HDF5 user
// block holding the checksum header, "RODEND-CHECKSUM 1\ncrc32 <8 hex>\nbytes <file size>\n"
// padded with NUL bytes: the CRC-32 (zlib.crc32) of every byte after the user block and the
// file's size. verify_case_file and verify_summary_file check it (every byte of the block too)
// before any reader opens the file with HDF5 (resume, merge, compare, report); HDF5 readers skip
// the user block.
#pragma once

#include <hdf5.h>

#include <array>
#include <cstdint>
#include <filesystem>
#include <string_view>

#include "sweep/results/atomic_file.hpp"

namespace rodend::results_detail {

/// Size of the user block of a case file: the checksum header (case_checksum_header).
constexpr hsize_t kUserBlock = 512;
constexpr std::string_view kChecksumMagic = "RODEND-CHECKSUM 1\n";
constexpr unsigned char kHdf5Signature[8] = {0x89, 'H', 'D', 'F', '\r', '\n', 0x1a, '\n'};

/// The user block of a case file, written before its HDF5 image (H5Fget_file_image leaves it
/// out): the checksum header "RODEND-CHECKSUM 1", then "crc32 <8 hex digits>" (CRC-32, as
/// zlib.crc32, of every byte after the user block, the image) and "bytes <file size>", one per
/// line, padded with NUL bytes to kUserBlock bytes.
std::array<unsigned char, kUserBlock> checksum_header(std::uint32_t crc, std::size_t file_size);
/// The same for an HDF5 image (the file without its user block); throws std::logic_error if it
/// does not start with HDF5's superblock.
std::array<unsigned char, kUserBlock> checksum_header(ByteSpan image);

/// verify_case_file, once per version of a file in this process: compare opens a case file
/// once per signal, and checks it the first time only. A file changed since (another inode,
/// size, modification or status-change time) is checked again.
void verify_case_file_once(const std::filesystem::path& path);

}  // namespace rodend::results_detail
