#include "transport_bar.h"

#include <QCheckBox>
#include <QComboBox>
#include <QHBoxLayout>
#include <QLabel>
#include <QSignalBlocker>
#include <QSlider>
#include <QStyle>
#include <QToolButton>
#include <algorithm>

namespace kfw {

namespace {
constexpr int kTickMs = 33;
}

TransportBar::TransportBar(QWidget* parent) : QWidget(parent) {
  auto* lay = new QHBoxLayout(this);
  lay->setContentsMargins(4, 2, 4, 2);
  auto button = [this, lay](QStyle::StandardPixmap icon, const QString& tip, const char* name) {
    auto* b = new QToolButton(this);
    b->setIcon(style()->standardIcon(icon));
    b->setToolTip(tip);
    b->setObjectName(name);
    lay->addWidget(b);
    return b;
  };
  start_ = button(QStyle::SP_MediaSkipBackward, "Back to the start", "transport.start");
  back_ = button(QStyle::SP_MediaSeekBackward, "Step back one sample", "transport.back");
  play_ = button(QStyle::SP_MediaPlay, "Play / pause the replay", "transport.play");
  fwd_ = button(QStyle::SP_MediaSeekForward, "Step forward one sample", "transport.step");
  seek_ = new QSlider(Qt::Horizontal, this);
  seek_->setObjectName("transport.seek");
  seek_->setToolTip("Seek");
  lay->addWidget(seek_, 1);
  time_ = new QLabel("t = – s", this);
  time_->setMinimumWidth(110);
  lay->addWidget(time_);
  lay->addWidget(new QLabel("speed", this));
  speed_ = new QComboBox(this);
  speed_->setObjectName("transport.speed");
  for (double s : {0.25, 0.5, 1.0, 2.0, 5.0, 10.0, 50.0}) {
    speed_->addItem(QString("%1×").arg(s), s);
  }
  speed_->setCurrentIndex(2);
  lay->addWidget(speed_);
  all_ = new QCheckBox("show all", this);
  all_->setObjectName("transport.all");
  all_->setToolTip("Show the whole run instead of data up to the replay cursor");
  all_->setChecked(true);
  lay->addWidget(all_);

  timer_.setInterval(kTickMs);
  connect(&timer_, &QTimer::timeout, this, &TransportBar::tick);
  connect(play_, &QToolButton::clicked, this, [this] { playing() ? pause() : play(); });
  connect(start_, &QToolButton::clicked, this, [this] { seek(0); });
  connect(back_, &QToolButton::clicked, this, [this] {
    pause();
    seek(index_ > 0 ? index_ - 1 : 0);
  });
  connect(fwd_, &QToolButton::clicked, this, [this] {
    pause();
    seek(index_ + 1);
  });
  connect(seek_, &QSlider::valueChanged, this, [this](int v) {
    if (static_cast<std::size_t>(v) != index_) seek(static_cast<std::size_t>(v));
  });
  connect(all_, &QCheckBox::toggled, this, [this](bool) { emitCursor(); });
}

void TransportBar::setTimes(const std::vector<double>& t) {
  const double keep = index_ < t_.size() ? t_[index_] : 0.0;
  t_ = t;
  {
    const QSignalBlocker b(seek_);
    seek_->setRange(0, t_.empty() ? 0 : static_cast<int>(t_.size() - 1));
  }
  const auto it = std::lower_bound(t_.begin(), t_.end(), keep);
  index_ =
      it == t_.end() ? (t_.empty() ? 0 : t_.size() - 1) : static_cast<std::size_t>(it - t_.begin());
  const QSignalBlocker b(seek_);
  seek_->setValue(static_cast<int>(index_));
  time_->setText(t_.empty() ? "t = – s" : QString("t = %1 s").arg(t_[index_], 0, 'f', 2));
}

std::size_t TransportBar::cursor() const {
  return showAll() ? static_cast<std::size_t>(-1) : index_;
}

bool TransportBar::showAll() const {
  return all_->isChecked();
}
void TransportBar::setShowAll(bool all) {
  all_->setChecked(all);
}
double TransportBar::speed() const {
  return speed_->currentData().toDouble();
}

void TransportBar::seek(std::size_t index) {
  if (t_.empty()) return;
  index_ = std::min(index, t_.size() - 1);
  play_time_ = t_[index_];
  if (showAll()) {
    const QSignalBlocker b(all_);
    all_->setChecked(false);
  }
  emitCursor();
}

void TransportBar::play() {
  if (t_.empty()) return;
  if (index_ + 1 >= t_.size()) index_ = 0;
  play_time_ = t_[index_];
  if (showAll()) {
    const QSignalBlocker b(all_);
    all_->setChecked(false);
  }
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPause));
  timer_.start();
  emitCursor();
}

void TransportBar::pause() {
  timer_.stop();
  play_->setIcon(style()->standardIcon(QStyle::SP_MediaPlay));
}

void TransportBar::tick() {
  if (t_.empty()) return pause();
  play_time_ += speed() * kTickMs / 1000.0;
  const auto it = std::upper_bound(t_.begin(), t_.end(), play_time_);
  const std::size_t next = it == t_.begin() ? 0 : static_cast<std::size_t>(it - t_.begin()) - 1;
  if (next + 1 >= t_.size()) {
    index_ = t_.size() - 1;
    pause();
  } else {
    index_ = next;
  }
  emitCursor();
}

void TransportBar::emitCursor() {
  {
    const QSignalBlocker b(seek_);
    seek_->setValue(static_cast<int>(index_));
  }
  if (!t_.empty()) time_->setText(QString("t = %1 s").arg(t_[index_], 0, 'f', 2));
  emit cursorChanged(cursor());
}

}  // namespace kfw
