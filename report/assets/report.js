// Draws every chart of a volcomp report with Vega (inlined before this script) as SVG, and says
// what it drew: window.volcompReport.ready resolves once every chart is drawn, .charts lists each
// chart's id and number of drawn items, .renderMs is the time from navigation start until then.
// A chart that cannot be drawn is reported on the console and in the page.
(function () {
  'use strict';
  var font = '"Segoe UI", system-ui, -apple-system, Roboto, "Helvetica Neue", Arial, ' +
      '"DejaVu Sans", sans-serif';
  var config = {
    background: null,
    axis: {
      labelFont: font, titleFont: font, labelFontSize: 11, titleFontSize: 11,
      titleFontWeight: 600, labelColor: '#3c4148', titleColor: '#1f2328', domainColor: '#8c959f',
      tickColor: '#8c959f', gridColor: '#e5e8eb'
    },
    legend: {
      labelFont: font, titleFont: font, labelFontSize: 11, titleFontSize: 11,
      titleFontWeight: 600, labelColor: '#3c4148', titleColor: '#1f2328'
    },
    title: {font: font, fontSize: 12, fontWeight: 600, color: '#1f2328', anchor: 'start'},
    text: {font: font, fontSize: 11, fill: '#3c4148'}
  };

  var report = {charts: [], views: {}, errors: [], renderMs: null};
  window.volcompReport = report;

  // Items of every non-group mark below a scenegraph node: what the chart actually drew.
  function countItems(node) {
    var count = 0;
    (node.items || []).forEach(function (item) {
      if (node.marktype !== 'group') count += 1;
      (item.items || []).forEach(function (child) { count += countItems(child); });
    });
    return count;
  }

  function draw(element) {
    var source = document.getElementById(element.getAttribute('data-spec'));
    var spec = JSON.parse(source.textContent);
    var view = new vega.View(vega.parse(spec, config), {
      renderer: 'svg', container: element, hover: true
    });
    report.views[element.id] = view;
    return view.runAsync().then(function () {
      var marks = countItems(view.scenegraph().root);
      report.charts.push({id: element.id, marks: marks});
      element.setAttribute('data-marks', String(marks));
    }, function (error) {
      var message = 'volcomp report: chart ' + element.id + ' could not be drawn: ' + error;
      element.textContent = message;
      element.className += ' chart-failed';
      report.errors.push(message);
      console.error(message);
    });
  }

  var charts = Array.prototype.slice.call(document.querySelectorAll('.chart[data-spec]'));
  report.ready = Promise.all(charts.map(function (element) {
    try {
      return draw(element);
    } catch (error) {
      report.errors.push(String(error));
      console.error('volcomp report: chart ' + element.id + ': ' + error);
      return Promise.resolve();
    }
  })).then(function () {
    report.renderMs = performance.now();
    document.documentElement.setAttribute('data-report', report.errors.length ? 'failed' : 'drawn');
    return report;
  });
})();
