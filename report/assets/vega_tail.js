  // What upstream's `vega` package index does for the parts the report uses: register the
  // transforms with the dataflow, then export the parser and the view.
  var util = require('vega-util');
  util.extend(require('vega-dataflow').transforms, require('vega-transforms'),
              require('vega-view-transforms'), require('vega-encode'));
  global.vega = {
    parse: require('vega-parser').parse,
    View: require('vega-view').View
  };
})(this);
