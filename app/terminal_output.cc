#include "app/terminal_output.h"

#include <iostream>

#include "core/base/messages.h"

namespace momenta {

std::streamsize TerminalTextBuffer::xsputn(const char* text, std::streamsize count) {
  std::string chunk = held_ + std::string(text, static_cast<size_t>(count));
  held_.clear();
  // A lead byte 0xC2 at the end waits for the next byte: with it, it may be a C1 control.
  if (!chunk.empty() && static_cast<unsigned char>(chunk.back()) == 0xc2) {
    held_ = "\xc2";
    chunk.pop_back();
  }
  const std::string safe = TerminalText(chunk);
  target_->sputn(safe.data(), static_cast<std::streamsize>(safe.size()));
  return count;
}

TerminalTextBuffer::int_type TerminalTextBuffer::overflow(int_type ch) {
  if (traits_type::eq_int_type(ch, traits_type::eof())) return traits_type::not_eof(ch);
  const char c = traits_type::to_char_type(ch);
  xsputn(&c, 1);
  return ch;
}

int TerminalTextBuffer::sync() { return target_->pubsync(); }

void TerminalTextBuffer::Finish() {
  if (!held_.empty()) target_->sputn(held_.data(), static_cast<std::streamsize>(held_.size()));
  held_.clear();
  target_->pubsync();
}

TerminalOutput::TerminalOutput()
    : cout_(std::cout.rdbuf()), cerr_(std::cerr.rdbuf()), out_(cout_), err_(cerr_) {
  std::cout.rdbuf(&out_);
  std::cerr.rdbuf(&err_);
}

TerminalOutput::~TerminalOutput() {
  std::cout.flush();
  std::cerr.flush();
  out_.Finish();
  err_.Finish();
  std::cout.rdbuf(cout_);
  std::cerr.rdbuf(cerr_);
}

}  // namespace momenta
