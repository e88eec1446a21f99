#pragma once
// HDF5 helpers shared by the trajectory writer and the dataset reader.
//  - QuietHdf5Errors: HDF5 prints its error stack to stderr by default; we report errors
//    ourselves, naming the file and the group, so each call into HDF5 silences it for its
//    duration and restores whatever the process had before (library calls leave process-wide
//    state alone).
//  - Hdf5Handle: an identifier closed by its own close function when it goes out of scope.
//  - skip_hdf5_exit_handler: no crash at exit after a failed write.

#include <hdf5.h>

namespace common {

class QuietHdf5Errors {
 public:
  QuietHdf5Errors() {
    H5Eget_auto2(H5E_DEFAULT, &handler_, &data_);
    H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr);
  }
  ~QuietHdf5Errors() { H5Eset_auto2(H5E_DEFAULT, handler_, data_); }
  QuietHdf5Errors(const QuietHdf5Errors&) = delete;
  QuietHdf5Errors& operator=(const QuietHdf5Errors&) = delete;

 private:
  H5E_auto2_t handler_ = nullptr;
  void* data_ = nullptr;
};

// HDF5 closes whatever is still open in an exit handler. After a failed write (a full disk) that
// handler walks the half-closed file and segfaults, so a clear "cannot write" error ended in
// signal 11. Each program calls this before its first HDF5 call: our files are closed by their
// Hdf5Handle or writer, and the process's memory goes back to the system anyway.
inline void skip_hdf5_exit_handler() {
  H5dont_atexit();
}

struct Hdf5Handle {
  hid_t id;
  herr_t (*close)(hid_t);
  ~Hdf5Handle() {
    if (id >= 0) close(id);
  }
  Hdf5Handle(hid_t identifier, herr_t (*closer)(hid_t)) : id(identifier), close(closer) {}
  Hdf5Handle(const Hdf5Handle&) = delete;
  Hdf5Handle& operator=(const Hdf5Handle&) = delete;
};

}  // namespace common
