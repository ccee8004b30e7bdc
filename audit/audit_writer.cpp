#include "audit/audit_writer.h"

#include <iterator>
#include <utility>

namespace tiltgate {

AuditWriter::AuditWriter(Sink sink, std::chrono::milliseconds retry_after)
    : sink_(std::move(sink)), retry_after_(retry_after), thread_([this] { run(); }) {}

AuditWriter::~AuditWriter() { close(); }

void AuditWriter::push(AuditRecord record) {
  std::unique_lock lock(mutex_);
  if (closed_) {
    write({std::move(record)});
    return;
  }
  queue_.push_back(std::move(record));
  lock.unlock();
  wake_.notify_one();
}

bool AuditWriter::flush() {
  std::unique_lock lock(mutex_);
  if (closed_) return !refused_;
  const std::uint64_t ticket = ++asked_;
  wake_.notify_one();
  // closed_: close() ran meanwhile, and wrote what was queued.
  answered_.wait(lock, [&] { return answered_for_ >= ticket || closed_; });
  return !refused_;
}

bool AuditWriter::close() {
  {
    const std::lock_guard lock(mutex_);
    if (closing_) return !refused_;
    closing_ = true;
  }
  wake_.notify_one();
  thread_.join();
  const std::lock_guard lock(mutex_);
  // Pushed while the thread was writing its last batch.
  if (!queue_.empty()) {
    std::vector<AuditRecord> rest(std::make_move_iterator(queue_.begin()),
                                  std::make_move_iterator(queue_.end()));
    queue_.clear();
    write(rest);
  }
  closed_ = true;
  answered_.notify_all();
  return !refused_;
}

std::uint64_t AuditWriter::batches() const {
  const std::lock_guard lock(mutex_);
  return batches_;
}

void AuditWriter::write(const std::vector<AuditRecord>& batch) {
  ++batches_;
  refused_ = !sink_(batch);
}

void AuditWriter::run() {
  std::unique_lock lock(mutex_);
  for (;;) {
    // After a refusal new records wait for the retry, so a full disk is not asked per record.
    const auto due = [this] {
      return closing_ || asked_ != answered_for_ || (!refused_ && !queue_.empty());
    };
    if (refused_)
      wake_.wait_for(lock, retry_after_, due);  // then tries again, due or not
    else
      wake_.wait(lock, due);
    std::vector<AuditRecord> batch(std::make_move_iterator(queue_.begin()),
                                   std::make_move_iterator(queue_.end()));
    queue_.clear();
    const std::uint64_t asked = asked_;
    const bool last = closing_;
    // The disk's time is the writer's alone: push() goes on meanwhile.
    lock.unlock();
    const bool written = sink_(batch);
    lock.lock();
    ++batches_;
    refused_ = !written;
    answered_for_ = asked;
    answered_.notify_all();
    if (last && queue_.empty()) return;
  }
}

}  // namespace tiltgate
