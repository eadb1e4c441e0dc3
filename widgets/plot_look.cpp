#include "plot_look.h"

#include <qcustomplot.h>

#include <QApplication>
#include <QFontMetricsF>
#include <QPalette>
#include <QStyleFactory>
#include <algorithm>
#include <cmath>

#include "plot_text.h"

namespace kfw {

namespace {

using Look = PlotLook;

const char* const kTheme = "kfwTheme";
const char* const kFontScale = "kfwFontScale";
const char* const kStrong = "kfwStrong";
const char* const kTitleText = "kfwTitleText";
const char* const kWrapped = "kfwTitleWrapped";
const char* const kWrapKey = "kfwTitleWrapKey";  // width|text of the last wrap

Look lookOf(const QCustomPlot* p) {
  Look l;
  if (p->property(kTheme).toInt() == 1) l.theme = Theme::kDark;
  const QVariant s = p->property(kFontScale);
  if (s.isValid()) l.font_scale = s.toDouble();
  l.strong = p->property(kStrong).toBool();
  return l;
}

const QColor kDarkBackground{30, 32, 36};
const QColor kDarkForeground{225, 225, 225};
const QColor kDarkGrid{72, 74, 80};

// Restyles one property of an element from its original value: the value plot_kit or the view
// gave it, recorded on first use and again whenever the owner changed it since we last set it.
template <typename T, typename Get, typename Set, typename F>
void restyleValue(QObject* o, const char* key, Get get, Set set, F f) {
  const QByteArray k(key);
  const QByteArray applied = k + "#set";
  const T now = get();
  const QVariant v = o->property(k.constData());
  const QVariant a = o->property(applied.constData());
  T orig = now;
  if (v.isValid() && a.isValid() && a.value<T>() == now) {
    orig = v.value<T>();
  } else {
    o->setProperty(k.constData(), QVariant::fromValue(now));
  }
  set(f(orig));
  o->setProperty(applied.constData(), QVariant::fromValue(T(get())));
}

bool isDark(const QColor& c) {
  return c.alpha() > 0 && c.lightness() < 70;
}

// A text, axis or line colour for the theme.
QColor ink(const QColor& c, Theme t) {
  if (t == Theme::kLight) return c;
  if (isDark(c)) return kDarkForeground;
  if (c.saturation() < 30 && c.lightness() > 150) return kDarkGrid;  // light grey grid lines
  return c;
}

// A band fill: an opaque pale colour (the colour over white) or a translucent one. Strong: the
// colour pushed away from white (a projector washes pale fills out). Dark: the same hue, dark.
QColor fill(const QColor& c, Theme t, bool strong) {
  QColor out = c;
  if (strong) {
    if (c.alpha() == 255) {
      auto deeper = [](int v) { return std::clamp(255 - (255 - v) * 5 / 2, 0, 255); };
      out = QColor(deeper(c.red()), deeper(c.green()), deeper(c.blue()));
    } else {
      out.setAlpha(std::min(255, c.alpha() * 2));
    }
  }
  if (t == Theme::kDark && out.alpha() == 255 && out.lightness() > 150) {
    out = QColor::fromHslF(out.hslHueF(), out.hslSaturationF(), 1.0 - out.lightnessF() * 0.75);
  }
  return out;
}

QPen dataPen(const QPen& orig, const Look& l) {
  QPen p = orig;
  QColor c = ink(orig.color(), l.theme);
  if (l.strong) {
    if (c.alpha() < 255 && c.alpha() > 0) c.setAlpha(255);  // ghosts: opaque
    p.setWidthF(std::max(2.0, orig.widthF() * 2.0));
  }
  p.setColor(c);
  return p;
}

QPen linePen(const QPen& orig, const Look& l, double strong_width) {
  QPen p = orig;
  p.setColor(ink(orig.color(), l.theme));
  if (l.strong) p.setWidthF(std::max(strong_width, orig.widthF() * strong_width));
  return p;
}

QFont scaled(const QFont& f, double s) {
  QFont g = f;
  if (f.pointSizeF() > 0) g.setPointSizeF(f.pointSizeF() * s);
  return g;
}

#define KFW_FONT(obj, key, getter, setter)                                                  \
  restyleValue<QFont>(                                                                      \
      obj, key, [obj] { return obj->getter(); }, [obj](const QFont& f) { obj->setter(f); }, \
      [&l](const QFont& f) { return scaled(f, l.font_scale); })
#define KFW_COLOR(obj, key, getter, setter)                                                  \
  restyleValue<QColor>(                                                                      \
      obj, key, [obj] { return obj->getter(); }, [obj](const QColor& c) { obj->setter(c); }, \
      [&l](const QColor& c) { return ink(c, l.theme); })
#define KFW_PEN(obj, key, getter, setter, width)                                           \
  restyleValue<QPen>(                                                                      \
      obj, key, [obj] { return obj->getter(); }, [obj](const QPen& v) { obj->setter(v); }, \
      [&l](const QPen& v) { return linePen(v, l, width); })

// The legend's own font and text colour are left alone: their setters overwrite every item's,
// and items added later (a pinned snapshot's) start from them unscaled, then get restyled.
void styleLegend(QCPLegend* lg, const Look& l) {
  restyleValue<QBrush>(
      lg, "kfwBrush", [lg] { return lg->brush(); }, [lg](const QBrush& b) { lg->setBrush(b); },
      [&l](const QBrush& b) {
        return l.theme == Theme::kDark ? QBrush(QColor(40, 42, 46, 220)) : b;
      });
  restyleValue<QPen>(
      lg, "kfwBorder", [lg] { return lg->borderPen(); },
      [lg](const QPen& p) { lg->setBorderPen(p); },
      [&l](QPen p) {
        if (l.theme == Theme::kDark) p.setColor(QColor(110, 110, 110));
        return p;
      });
  for (int i = 0; i < lg->itemCount(); ++i) {
    QCPAbstractLegendItem* it = lg->item(i);
    if (!it) continue;  // an empty cell of a wrapped legend row
    KFW_FONT(it, "kfwFont", font, setFont);
    KFW_COLOR(it, "kfwText", textColor, setTextColor);
  }
}

void styleAxis(QCPAxis* a, const Look& l) {
  KFW_FONT(a, "kfwLabelFont", labelFont, setLabelFont);
  KFW_FONT(a, "kfwTickFont", tickLabelFont, setTickLabelFont);
  KFW_COLOR(a, "kfwLabelColor", labelColor, setLabelColor);
  KFW_COLOR(a, "kfwTickColor", tickLabelColor, setTickLabelColor);
  KFW_PEN(a, "kfwBasePen", basePen, setBasePen, 1.5);
  KFW_PEN(a, "kfwTickPen", tickPen, setTickPen, 1.5);
  KFW_PEN(a, "kfwSubTickPen", subTickPen, setSubTickPen, 1.5);
  QCPGrid* g = a->grid();
  KFW_PEN(g, "kfwPen", pen, setPen, 1.0);
  KFW_PEN(g, "kfwSub", subGridPen, setSubGridPen, 1.0);
  KFW_PEN(g, "kfwZero", zeroLinePen, setZeroLinePen, 1.0);
}

void restyle(QCustomPlot* p) {
  const Look l = lookOf(p);
  restyleValue<QBrush>(
      p, "kfwBackground", [p] { return p->property("kfwBg").value<QBrush>(); },
      [p](const QBrush& b) {
        p->setProperty("kfwBg", QVariant::fromValue(b));
        p->setBackground(b);
      },
      [&l](const QBrush& b) {
        if (l.theme == Theme::kDark) return QBrush(kDarkBackground);
        return b.style() == Qt::NoBrush ? QBrush(Qt::white) : b;
      });
  for (QCPLayoutElement* e : p->plotLayout()->elements(true)) {
    if (auto* t = qobject_cast<QCPTextElement*>(e)) {
      KFW_FONT(t, "kfwFont", font, setFont);
      KFW_COLOR(t, "kfwText", textColor, setTextColor);
    } else if (auto* lg = qobject_cast<QCPLegend*>(e)) {
      styleLegend(lg, l);
    } else if (auto* cs = qobject_cast<QCPColorScale*>(e)) {
      // A colour scale's axis starts from QFont(), the application's (× the presentation's
      // scale when made while presenting): the plot's font first.
      QCPAxis* a = cs->axis();
      if (!a->property("kfwLabelFont").isValid()) {
        a->setLabelFont(p->font());
        a->setTickLabelFont(p->font());
      }
      styleAxis(a, l);
    }
  }
  for (QCPAxisRect* r : p->axisRects()) {
    for (QCPLayoutElement* e : r->insetLayout()->elements(true)) {
      if (auto* lg = qobject_cast<QCPLegend*>(e)) styleLegend(lg, l);
    }
    for (QCPAxis* a : r->axes())
      styleAxis(a, l);
  }
  for (int i = 0; i < p->plottableCount(); ++i) {
    QCPAbstractPlottable* g = p->plottable(i);
    restyleValue<QPen>(
        g, "kfwPen", [g] { return g->pen(); }, [g](const QPen& pen) { g->setPen(pen); },
        [&l](const QPen& pen) { return dataPen(pen, l); });
    restyleValue<QBrush>(
        g, "kfwBrush", [g] { return g->brush(); }, [g](const QBrush& b) { g->setBrush(b); },
        [&l](QBrush b) {
          if (b.style() != Qt::NoBrush) b.setColor(fill(b.color(), l.theme, l.strong));
          return b;
        });
  }
  for (int i = 0; i < p->itemCount(); ++i) {
    QCPAbstractItem* it = p->item(i);
    if (auto* line = qobject_cast<QCPItemStraightLine*>(it)) {
      KFW_PEN(line, "kfwPen", pen, setPen, 2.0);
    } else if (auto* t = qobject_cast<QCPItemText*>(it)) {
      KFW_FONT(t, "kfwFont", font, setFont);
      KFW_COLOR(t, "kfwColor", color, setColor);
      restyleValue<QBrush>(
          t, "kfwBrush", [t] { return t->brush(); }, [t](const QBrush& b) { t->setBrush(b); },
          [&l](QBrush b) {
            if (l.theme == Theme::kDark && b.style() != Qt::NoBrush && b.color().lightness() > 150)
              b.setColor(QColor(40, 42, 46, b.color().alpha()));
            return b;
          });
    }
  }
}

#undef KFW_FONT
#undef KFW_COLOR
#undef KFW_PEN

}  // namespace

PlotLook plotLook(const QCustomPlot* plot) {
  return lookOf(plot);
}

void setPlotLook(QCustomPlot* plot, const PlotLook& look) {
  plot->setProperty(kTheme, look.theme == Theme::kDark ? 1 : 0);
  plot->setProperty(kFontScale, look.font_scale);
  plot->setProperty(kStrong, look.strong);
  restyle(plot);
}

void applyTheme(QCustomPlot* plot, Theme theme) {
  plot->setProperty(kTheme, theme == Theme::kDark ? 1 : 0);
  restyle(plot);
}

Theme currentTheme(const QCustomPlot* plot) {
  return lookOf(plot).theme;
}

void applyPresentationLook(QCustomPlot* plot, double font_scale, bool strong) {
  plot->setProperty(kFontScale, font_scale);
  plot->setProperty(kStrong, strong);
  restyle(plot);
}

void applyWindowTheme(QWidget* window, Theme theme) {
  Q_UNUSED(window);
  static const QPalette platform = QApplication::palette();
  if (theme == Theme::kLight) {
    QApplication::setPalette(platform);
    return;
  }
  QApplication::setStyle(QStyleFactory::create("Fusion"));
  QPalette p;
  p.setColor(QPalette::Window, QColor(45, 47, 52));
  p.setColor(QPalette::WindowText, kDarkForeground);
  p.setColor(QPalette::Base, QColor(30, 32, 36));
  p.setColor(QPalette::AlternateBase, QColor(45, 47, 52));
  p.setColor(QPalette::ToolTipBase, QColor(45, 47, 52));
  p.setColor(QPalette::ToolTipText, kDarkForeground);
  p.setColor(QPalette::Text, kDarkForeground);
  p.setColor(QPalette::Button, QColor(53, 55, 60));
  p.setColor(QPalette::ButtonText, kDarkForeground);
  p.setColor(QPalette::BrightText, Qt::red);
  p.setColor(QPalette::Highlight, QColor(42, 130, 218));
  p.setColor(QPalette::HighlightedText, Qt::black);
  p.setColor(QPalette::Disabled, QPalette::Text, QColor(120, 120, 120));
  p.setColor(QPalette::Disabled, QPalette::ButtonText, QColor(120, 120, 120));
  QApplication::setPalette(p);
}

QString wrapText(const QString& text, const QFont& font, int width) {
  const QFontMetricsF fm(font);
  if (fm.horizontalAdvance(text) <= width) return text;
  QStringList lines;
  QString line;
  for (const QString& word : text.split(' ', Qt::SkipEmptyParts)) {
    const QString next = line.isEmpty() ? word : line + ' ' + word;
    if (!line.isEmpty() && fm.horizontalAdvance(next) > width) {
      lines << line;
      line = word;
    } else {
      line = next;
    }
  }
  if (!line.isEmpty()) lines << line;
  return lines.join('\n');
}

void setTitle(QCustomPlot* plot, const QString& title) {
  auto* t = plot->findChild<QCPTextElement*>("title");
  if (!t) return;
  const bool wrapped = t->property(kWrapped).toString() == t->text();
  const QString now =
      wrapped && t->property(kTitleText).isValid() ? t->property(kTitleText).toString() : t->text();
  if (now != plot::typeset(title)) t->setText(plot::typeset(title));
}

bool wrapTitlesToWidth(QCustomPlot* plot) {
  bool changed = false;
  if (plot->property(kExportingProperty).toBool()) return false;
  // A resize sets the layout's outer rect; its cells follow at the next replot. A plot resized
  // while out of view (drawn when shown) would wrap to its old cells: lay them out now.
  QCPLayoutGrid* top = plot->plotLayout();
  int right = top->rect().left();
  for (QCPLayoutElement* e : top->elements(false)) {
    if (e) right = std::max(right, e->outerRect().right());
  }
  if (right != top->rect().right()) {
    for (auto phase :
         {QCPLayoutElement::upPreparation, QCPLayoutElement::upMargins, QCPLayoutElement::upLayout})
      top->update(phase);
  }
  for (QCPLayoutElement* e : plot->plotLayout()->elements(true)) {
    auto* t = qobject_cast<QCPTextElement*>(e);
    if (!t) continue;
    // The title's own cell once laid out (a title over one column of several, the heat map's
    // beside its colour scale, has less than the plot's width).
    const int cell = t->rect().width();
    const int width = cell > 0 ? std::min(cell, plot->width() - 12) : plot->width() - 12;
    // Nothing to do when neither the title nor the width changed since the last wrap (this
    // runs before every replot).
    const QString key = QString::number(width) + '|' + t->text();
    if (t->property(kWrapKey).toString() == key) continue;
    // The unwrapped text: recorded, unless the view set a new title since the last wrap.
    QString text = t->text();
    if (t->property(kWrapped).toString() == text && t->property(kTitleText).isValid()) {
      text = t->property(kTitleText).toString();
    }
    t->setProperty(kTitleText, text);
    const QString wrapped = wrapText(text, t->font(), width);
    t->setProperty(kWrapped, wrapped);
    if (wrapped != t->text()) {
      t->setText(wrapped);
      changed = true;
    }
    t->setProperty(kWrapKey, QString::number(width) + '|' + t->text());
  }
  return changed;
}

}  // namespace kfw
