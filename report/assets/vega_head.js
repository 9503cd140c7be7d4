// A CommonJS-style loader for Vega's per-package UMD files: each package is registered as a
// factory and instantiated on first require, so that packages load in dependency order.
(function (global) {
  'use strict';
  var factories = Object.create(null);
  var modules = Object.create(null);
  function define(name, factory) {
    factories[name] = factory;
  }
  function require(name) {
    if (!(name in modules)) {
      if (!(name in factories)) throw new Error('Vega bundle: package ' + name + ' is missing');
      var module = {exports: {}};
      modules[name] = module;
      factories[name].call(module.exports, module.exports, module, require);
    }
    return modules[name].exports;
  }
